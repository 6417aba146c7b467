#!/usr/bin/python3
"""Every X server that the project's scripts and tests start runs with -noreset.

An X server without -noreset resets when its last client leaves, and it hangs up on a
connection made during the reset. A pvserver process closes the connection of ParaView's
OpenGL check and opens its window's 0.2 ms later, so under such a server it lost its
display in 2 of 4 runs of pvpython.test_client_server (docs/client-server.md, "An X server
that resets"). This check finds the X servers started by
  - shell scripts (*.sh, or a shell shebang): a command word `Xvfb` or `xvfb-run`
    (comments, here-documents and `command -v xvfb-run` are not starts);
  - Python files: a list literal whose first element is "Xvfb" or "xvfb-run", and a
    string passed to a call that starts one ("xvfb-run -a ...");
and fails for each one whose command (its continuation lines included; for xvfb-run, the
server arguments of -s) has no -noreset. The examples' docstrings (`xvfb-run -a pvbatch`,
one process, as a user types it) are not commands.

Usage: check_x_servers.py [REPO]   (exit 0 when every start has -noreset, 1 otherwise)
"""

import ast
import os
import re
import shlex
import sys

SCANNED = ("scripts", "Testing", "Examples", ".ci", "Plugin")
SKIPPED_DIRS = {".cache", "build", ".git"}
SERVERS = ("Xvfb", "xvfb-run")
SHELL_START = re.compile(r"(?:^|[;&|(]\s*|\s)(Xvfb|xvfb-run)\s")


def shell_starts(script):
    """(line number, command text) of each X server a shell script starts."""
    starts = []
    lines = script.split("\n")
    number = 0
    while number < len(lines):
        first = number
        line = lines[number]
        # Continuation lines belong to the command.
        while line.endswith("\\") and number + 1 < len(lines):
            number += 1
            line = line[:-1] + " " + lines[number]
        number += 1
        heredoc = re.search(r"<<-?\s*'?(\w+)'?", line)
        if heredoc:  # its body is data
            while number < len(lines) and lines[number].strip() != heredoc.group(1):
                number += 1
            number += 1
        if line.strip().startswith("#"):
            continue
        try:
            lexer = shlex.shlex(re.sub(r"([;&|()])", r" \1 ", line), posix=True)
            lexer.whitespace_split = True
            lexer.commenters = "#"
            words = list(lexer)
        except ValueError:
            continue
        for i, word in enumerate(words):
            if word in SERVERS and not (i > 0 and words[i - 1] in ("-v", "which", "-V")):
                starts.append((first + 1, " ".join(words[i:])))
                break
    return starts


def python_starts(source):
    """(line number, command text) of each X server a Python file starts."""
    try:
        tree = ast.parse(source)
    except SyntaxError:
        return []
    starts = []
    for node in ast.walk(tree):
        if isinstance(node, (ast.List, ast.Tuple)) and node.elts:
            head = node.elts[0]
            names_only = all(isinstance(e, ast.Constant) and e.value in SERVERS
                             for e in node.elts)  # a list of the names, not a command
            if isinstance(head, ast.Constant) and head.value in SERVERS and not names_only:
                text = " ".join(e.value if isinstance(e, ast.Constant) and
                                isinstance(e.value, str) else "?" for e in node.elts)
                starts.append((node.lineno, text))
        elif isinstance(node, ast.Call):
            for arg in node.args:
                if isinstance(arg, ast.Constant) and isinstance(arg.value, str) and \
                        SHELL_START.search(" " + arg.value):
                    starts.append((arg.lineno, arg.value))
    return starts


def x_server_starts(repo):
    """[(path relative to repo, line, command)] of every X server started."""
    found = []
    for top in SCANNED:
        for root, dirs, files in os.walk(os.path.join(repo, top)):
            dirs[:] = [d for d in dirs if d not in SKIPPED_DIRS]
            for name in sorted(files):
                path = os.path.join(root, name)
                try:
                    text = open(path, encoding="utf-8").read()
                except (UnicodeDecodeError, OSError):
                    continue
                if name.endswith(".sh") or text.startswith(("#!/bin/sh", "#!/usr/bin/env bash",
                                                           "#!/bin/bash")):
                    starts = shell_starts(text)
                elif name.endswith(".py"):
                    starts = python_starts(text)
                else:
                    continue
                found += [(os.path.relpath(path, repo), line, command)
                          for line, command in starts]
    return found


def main(argv):
    repo = argv[1] if len(argv) > 1 else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    starts = x_server_starts(repo)
    failed = 0
    for path, line, command in starts:
        ok = "-noreset" in command
        failed += not ok
        print("%s %s:%d: %s" % ("ok  " if ok else "FAIL:", path, line,
                                command if ok else command + "  (no -noreset)"))
    print("%d X server starts, %d without -noreset" % (len(starts), failed))
    if not starts:
        print("FAIL: no X server start found (the scan is broken)")
        return 1
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

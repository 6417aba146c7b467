#!/usr/bin/python3
"""Every external program that the project's scripts, tests and examples call is installed
by scripts/setup.sh.

A fresh Debian 12 machine has only what scripts/setup.sh installs. A test that calls a
program nobody installs passes where someone installed it by hand and fails everywhere
else (xwd and ImageMagick's convert did). This check finds the programs called:
  - shell scripts (*.sh): the command words of every simple command;
  - Python files: subprocess/os calls with a literal program (lists, and strings run by a
    shell: `sh -c "..."`, shell=True, os.system), shutil.which("...");
  - CMake files: find_program(VAR name ...);
and for each one asks dpkg which Debian package owns it. A program passes when its package
is in setup.sh's list, is one of Debian's required/important/essential packages (on every
Debian system), or is pulled in by a listed package (Depends/Pre-Depends, recursively, as
apt installs them). A program that is not installed at all fails: setup.sh has to install it.

Python modules that the Python files import (outside try/except ImportError) are checked
the same way, as Debian's /usr/bin/python3 (the Python of pvbatch and pvpython) finds them.

Usage: check_setup_programs.py [--setup SETUP_SH] [REPO]   (exit 0 when all pass, 1 otherwise)
"""

import ast
import os
import re
import shlex
import subprocess
import sys

# Folders whose files run on the developer's or the CI machine. Testing/gpu runs on the GPU
# machine (no ParaView, no Debian packages of ours); .cache holds fetched data.
SCANNED = ("scripts", "Testing", "Examples", ".ci", "Plugin")
SKIPPED_DIRS = {os.path.join("Testing", "gpu"), ".cache", "build", ".git"}

# Programs that the project uses only where present, each with the reason it may be absent.
OPTIONAL = {
    "nvcc": "CUDA compiler: the CUDA kernels build only where it is found (scripts/build.sh)",
    "sudo": "setup.sh uses it only when not root",
    "apt-get": "setup.sh's installer itself (Debian's apt, required)",
}

SHELL_WORDS = {
    "if", "then", "else", "elif", "fi", "for", "in", "do", "done", "while", "until", "case",
    "esac", "function", "select", "time", "!", "{", "}", "[[", "]]", "((", "))",
    # builtins
    ".", ":", "[", "alias", "break", "cd", "command", "continue", "declare", "echo", "eval",
    "exec", "exit", "export", "false", "getopts", "hash", "local", "printf", "pwd", "read",
    "readonly", "return", "set", "shift", "source", "test", "trap", "true", "type", "ulimit",
    "umask", "unset", "wait", "kill", "jobs", "fg", "bg", "disown", "let", "mapfile",
}
# Programs that run the next word as the command (their options skipped).
WRAPPERS = {"sudo", "env", "exec", "timeout", "xvfb-run", "setsid", "nice", "nohup",
            "mpiexec", "mpirun", "stdbuf", "command", "time"}
SEPARATORS = {"|", "||", "&&", ";", "&", "|&", "(", ")", "$(", "`", "then", "do", "else",
              "elif", "{", "!", "while", "until", "if"}


def command_words(script):
    """The programs a shell script's simple commands start with (literal words only)."""
    found = set()
    text = re.sub(r"\\\n", " ", script)
    # Here-documents are data, not commands.
    text = re.sub(r"<<-?\s*'?(\w+)'?\n.*?\n\s*\1\n", "\n", text, flags=re.S)
    # Neither are array assignments (name=( ... ), over several lines), arithmetic
    # $(( ... )), redirections (2>&1, >file) or case patterns (a|b) ...).
    text = re.sub(r"(^|\n)\s*#[^\n]*", "\n", text)
    text = re.sub(r"\b\w+=\((.*?)\)", " ", text, flags=re.S)
    text = re.sub(r"\$\(\(.*?\)\)", " ", text)
    text = re.sub(r"\d*[<>]&\d*-?|\d*>>?|<", " ", text)
    text = re.sub(r"\bcase\b.*?\bin\b", " ", text)
    text = re.sub(r"(^|\n)\s*[^\s()]+\)", "\n", text)
    # Functions the script defines are not programs.
    functions = set(re.findall(r"(?:^|\n)\s*(?:function\s+)?([\w-]+)\s*\(\)", text))
    for line in text.splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        # Put spaces around operators and command substitutions so shlex sees them.
        line = re.sub(r"(\$\(|`|\|\||&&|\|&|[|;&()])", r" \1 ", line)
        try:
            lexer = shlex.shlex(line, posix=True, punctuation_chars=False)
            lexer.whitespace_split = True
            lexer.commenters = "#"
            words = list(lexer)
        except ValueError:
            continue
        expect = True
        wrapper = None
        for w in words:
            if w in SEPARATORS:
                expect, wrapper = True, None
                continue
            if not expect:
                continue
            if re.match(r"^[A-Za-z_][A-Za-z0-9_]*=", w):  # VAR=value before a command
                continue
            if wrapper is not None and (w.startswith("-") or re.match(r"^[0-9.]+[smh]?$", w)):
                continue  # the wrapper's options and their values (timeout 900, -n 2)
            expect = False
            if w in WRAPPERS:
                if w not in SHELL_WORDS:
                    found.add(w)
                wrapper, expect = w, True
                continue
            wrapper = None
            if w in SHELL_WORDS or w in functions or w.endswith(")") or not re.match(r"^[A-Za-z0-9][\w.+-]*$", w):
                continue  # keywords, functions, paths, variables: not a program on PATH
            found.add(w)
    return found


def python_imports(source):
    """Top-level modules a Python file imports unconditionally (an import inside a
    try/except ImportError block is optional)."""
    try:
        tree = ast.parse(source)
    except SyntaxError:
        return set()
    optional = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Try) and any(
                isinstance(h.type, ast.Name) and h.type.id in ("ImportError",
                                                              "ModuleNotFoundError", "Exception")
                or h.type is None for h in node.handlers):
            for inner in node.body:
                for sub in ast.walk(inner):
                    optional.add(id(sub))
    found = set()
    for node in ast.walk(tree):
        if id(node) in optional:
            continue
        if isinstance(node, ast.Import):
            found.update(a.name.split(".")[0] for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.add(node.module.split(".")[0])
    return found


def python_programs(source):
    """Programs that a Python file starts (literal names only)."""
    found = set()
    try:
        tree = ast.parse(source)
    except SyntaxError:
        return found
    constants = {t.id: n.value.value for n in tree.body if isinstance(n, ast.Assign)
                 and isinstance(n.value, ast.Constant) and isinstance(n.value.value, str)
                 for t in n.targets if isinstance(t, ast.Name)}
    calls = ("run", "Popen", "call", "check_call", "check_output", "system", "execvp",
             "execlp", "spawnlp", "which", "getoutput", "getstatusoutput")
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        name = node.func.attr if isinstance(node.func, ast.Attribute) else \
            node.func.id if isinstance(node.func, ast.Name) else None
        module = node.func.value.id if isinstance(node.func, ast.Attribute) and \
            isinstance(node.func.value, ast.Name) else None
        if name not in calls or not node.args or module not in ("subprocess", "os", "shutil"):
            continue
        first = node.args[0]
        shell = name in ("system", "getoutput", "getstatusoutput") or any(
            k.arg == "shell" and isinstance(k.value, ast.Constant) and k.value.value
            for k in node.keywords)
        if isinstance(first, (ast.List, ast.Tuple)) and first.elts:
            head = first.elts[0]
            if isinstance(head, ast.Constant) and isinstance(head.value, str):
                found.add(os.path.basename(head.value))
                if head.value in ("sh", "bash") and len(first.elts) > 2:
                    script = first.elts[2]
                    text = _literal_text(script, constants)
                    if text:
                        found |= command_words(text)
        else:
            text = _literal_text(first, constants)
            if text is None:
                continue
            if shell:
                found |= command_words(text)
            elif name in ("which", "execvp", "execlp", "spawnlp"):
                found.add(os.path.basename(text))
            elif re.match(r"^[\w.+-]+$", text):
                found.add(text)
    return found


def _literal_text(node, constants):
    """The text of a string expression built from constants ('a' + NAME, 'a %s' % x);
    None when nothing of it is known."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    if isinstance(node, ast.Name):
        return constants.get(node.id)
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mod):
        return _literal_text(node.left, constants)
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
        parts = [_literal_text(node.left, constants), _literal_text(node.right, constants)]
        return None if parts == [None, None] else "".join(p or " " for p in parts)
    if isinstance(node, ast.JoinedStr):
        return "".join(v.value for v in node.values
                       if isinstance(v, ast.Constant) and isinstance(v.value, str))
    return None


def cmake_programs(source):
    found = set()
    for m in re.finditer(r"find_program\s*\(\s*\w+\s+(?:NAMES\s+)?([\w.+-]+)", source):
        found.add(m.group(1))
    return found


def programs_called(repo):
    """{program: [files that call it]}, {python module: [files that import it]}"""
    called, imported = {}, {}
    for top in SCANNED:
        for root, dirs, files in os.walk(os.path.join(repo, top)):
            rel = os.path.relpath(root, repo)
            dirs[:] = [d for d in dirs if os.path.join(rel, d) not in SKIPPED_DIRS]
            for f in files:
                path = os.path.join(root, f)
                try:
                    text = open(path, encoding="utf-8").read()
                except (UnicodeDecodeError, OSError):
                    continue
                if f.endswith(".sh") or text.startswith(("#!/bin/sh", "#!/usr/bin/env bash",
                                                        "#!/bin/bash")):
                    names = command_words(text)
                elif f.endswith(".py"):
                    names = python_programs(text)
                    for m in python_imports(text):
                        imported.setdefault(m, []).append(os.path.relpath(path, repo))
                elif f == "CMakeLists.txt" or f.endswith(".cmake"):
                    names = cmake_programs(text)
                else:
                    continue
                for n in names:
                    called.setdefault(n, []).append(os.path.relpath(path, repo))
    return called, imported


def project_names(repo):
    """Names the project itself provides: its scripts and the executables it builds."""
    names = set()
    for root, _, files in os.walk(repo):
        if "/.git" in root or "/.cache" in root:
            continue
        names.update(files)
    text = ""
    for root, _, files in os.walk(repo):
        if "/.git" in root or "/build" in root:
            continue
        for f in files:
            if f == "CMakeLists.txt":
                text += open(os.path.join(root, f), encoding="utf-8").read()
    names.update(re.findall(r"add_executable\s*\(\s*([\w.+-]+)", text))
    # Shell functions of the project's scripts, which other scripts source (e.g.
    # Testing/Python/pvserver_control.sh): called like programs, provided by the project.
    for root, _, files in os.walk(repo):
        if "/.git" in root or "/build" in root or "/.cache" in root:
            continue
        for f in files:
            if f.endswith(".sh"):
                source = open(os.path.join(root, f), encoding="utf-8", errors="replace").read()
                names.update(re.findall(r"(?:^|\n)\s*(?:function\s+)?([\w-]+)\s*\(\)\s*\{", source))
    return names


def module_owner(module):
    """(file, package) of a Python module as Debian's python3 finds it; (None, None) when
    it is not installed; (file, None) for the standard library."""
    import importlib.util
    if module in sys.stdlib_module_names or module in sys.builtin_module_names:
        return "stdlib", None
    try:
        spec = importlib.util.find_spec(module)
    except (ImportError, ValueError):
        spec = None
    if spec is None or not spec.origin:
        return None, None
    path = spec.origin if spec.origin != "namespace" else list(spec.submodule_search_locations)[0]
    return path, file_owner(path) or "(no package)"


def setup_packages(setup):
    text = open(setup, encoding="utf-8").read()
    body = re.search(r"packages=\((.*?)\n\)", text, re.S).group(1)
    words = []
    for line in body.splitlines():
        words += line.split("#", 1)[0].split()
    return set(words)


def dpkg_fields(packages, fields):
    """{package: {field: value}} of installed packages."""
    if not packages:
        return {}
    fmt = "${Package}\t" + "\t".join("${%s}" % f for f in fields) + "\n"
    out = subprocess.run(["dpkg-query", "-W", "-f", fmt] + sorted(packages),
                         stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True).stdout
    result = {}
    for line in out.splitlines():
        parts = line.split("\t")
        result[parts[0]] = dict(zip(fields, parts[1:]))
    return result


def installed_closure(roots):
    """The listed packages and everything they depend on (Depends, Pre-Depends)."""
    seen, todo = set(), set(roots)
    while todo:
        info = dpkg_fields(todo, ["Depends", "Pre-Depends", "Provides"])
        seen |= todo
        nxt = set()
        for fields in info.values():
            for dep in (fields.get("Depends", "") + "," + fields.get("Pre-Depends", "")).split(","):
                for alt in dep.split("|"):
                    name = alt.strip().split(" ")[0].split(":")[0]
                    if name and name not in seen:
                        nxt.add(name)
        # Virtual packages (e.g. 'awk') are satisfied by installed providers.
        todo = nxt - seen
    return seen


_OWNERS = {}


def file_owner(path):
    """The package that installed `path` (dpkg's file lists, read once: one `dpkg -S` per
    file takes a second); also under the other half of Debian's merged /usr (/bin = /usr/bin)
    and the path a symbolic link points to. None when no package lists it."""
    if not _OWNERS:
        info = "/var/lib/dpkg/info"
        for name in os.listdir(info):
            if name.endswith(".list"):
                package = name[:-len(".list")].split(":")[0]
                with open(os.path.join(info, name), encoding="utf-8", errors="replace") as f:
                    for line in f:
                        _OWNERS.setdefault(line.rstrip("\n"), package)
    candidates = [path, os.path.realpath(path)]
    for c in list(candidates):
        for a, b in (("/usr/bin/", "/bin/"), ("/usr/sbin/", "/sbin/"), ("/usr/lib/", "/lib/")):
            if c.startswith(a):
                candidates.append(b + c[len(a):])
            elif c.startswith(b):
                candidates.append(a + c[len(b):])
    for c in candidates:
        if c in _OWNERS:
            return _OWNERS[c]
    return None


def owner(program):
    """(path, package) of the program on Debian's PATH; (None, None) when not installed."""
    for d in ("/usr/bin", "/bin", "/usr/sbin", "/sbin"):
        path = os.path.join(d, program)
        if os.path.exists(path):
            break
    else:
        return None, None
    return path, file_owner(path) or "(no package)"


def main(argv):
    args = list(argv[1:])
    setup = None
    if "--setup" in args:
        i = args.index("--setup")
        setup = args[i + 1]
        del args[i:i + 2]
    repo = os.path.abspath(args[0] if args else os.path.join(os.path.dirname(__file__), ".."))
    setup = setup or os.path.join(repo, "scripts", "setup.sh")
    called, imported = programs_called(repo)
    ours = project_names(repo)
    listed = setup_packages(setup)
    closure = installed_closure(listed)
    base = {p for p, f in dpkg_fields(set(x.split()[0] for x in subprocess.run(
        ["dpkg-query", "-W", "-f", "${Package}\n"], stdout=subprocess.PIPE, text=True
    ).stdout.split()), ["Priority", "Essential"]).items()
        if f.get("Essential") == "yes" or f.get("Priority") in ("required", "important")}

    def provenance(pkg):
        """Why a package is on a fresh machine after setup.sh; None when it is not."""
        return "listed" if pkg in listed else "base system" if pkg in base else \
            "dependency of a listed package" if pkg in closure else None

    failures = []
    rows = []

    def judge(name, row, users, verb, path, pkg, unowned_ok):
        """A row for `name` (a program or a Python module) found at `path` in package `pkg`,
        or a failure when it is missing or no package that setup.sh brings provides it;
        `users`: the files that call or import it; `unowned_ok`: a file of no package (a
        module of Python itself) needs no row."""
        where = ", ".join(sorted(set(users))[:3])
        if path is None:
            failures.append("%s (%s by %s) is not installed: add its Debian package to "
                            "scripts/setup.sh" % (name, verb, where))
        elif pkg is None and unowned_ok:
            return
        elif provenance(pkg) is None:
            failures.append("%s (%s, %s by %s) comes from package %s, which scripts/setup.sh "
                            "does not install" % (name, path, verb, where, pkg))
        else:
            rows.append("%-14s %-28s %s" % (row, pkg, provenance(pkg)))

    for program in sorted(called):
        if program not in ours and program not in OPTIONAL:
            judge(program, program, called[program], "called", *owner(program),
                  unowned_ok=False)
    own_modules = {os.path.splitext(n)[0] for n in ours if n.endswith(".py")} | \
        {d for d in os.listdir(os.path.join(repo, "Plugin", "MultichannelExplorer"))}
    for module in sorted(imported):
        if module not in own_modules and module != "__future__":
            judge("Python module " + module, "py:" + module, imported[module], "imported",
                  *module_owner(module), unowned_ok=True)
    print("programs and Python modules used by scripts, tests and examples: %d checked"
          % len(rows))
    for r in rows:
        print("  " + r)
    for f in failures:
        print("FAIL: " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

"""Every relative link of README.md and docs/*.md points to a file of the repository, and
every #anchor to a heading of the page it names.

    check_docs_links.py REPO [FILE.md ...]

Checks README.md and docs/*.md of REPO (or the FILEs given, relative to REPO). A link is
[text](target) or ![alt](target) outside code blocks and inline code; http(s), mailto and
other URLs with a scheme are not checked (no network). Anchors are the headings' GitHub
slugs: lower case, punctuation other than '-' and '_' dropped, spaces as '-', a repeated
heading numbered '-1', '-2'. A target outside REPO counts as dead: a fresh clone does not
have it. Prints one FAIL line per dead link (file:line, the link, why) and exits 1 when
there is one."""
import glob
import os
import re
import sys

LINK = re.compile(r"!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")


def strip_code(lines):
    """The lines with fenced code blocks blanked and inline code spans removed (so that a
    link written as an example in code is not checked)."""
    out, fenced = [], False
    for line in lines:
        if line.lstrip().startswith("```"):
            fenced = not fenced
            out.append("")
            continue
        out.append("" if fenced else re.sub(r"`[^`]*`", "", line))
    return out


def slug(text):
    """GitHub's anchor of a heading: rendered text (code spans keep their content, links
    their text), lower case, only letters, digits, '-', '_' and spaces kept, spaces as '-'."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", text)
    text = text.replace("`", "").replace("*", "")
    text = text.strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path, cache={}):
    if path not in cache:
        seen, found, fenced = {}, set(), False
        with open(path, encoding="utf-8") as f:
            for line in f:
                if line.lstrip().startswith("```"):
                    fenced = not fenced
                    continue
                m = None if fenced else HEADING.match(line.rstrip("\n"))
                if not m:
                    continue
                base = slug(m.group(2))
                n = seen.get(base, 0)
                seen[base] = n + 1
                found.add(base if n == 0 else "%s-%d" % (base, n))
        cache[path] = found
    return cache[path]


def check(repo, rel):
    path = os.path.join(repo, rel)
    problems = []
    with open(path, encoding="utf-8") as f:
        lines = strip_code(f.read().split("\n"))
    for number, line in enumerate(lines, 1):
        for m in LINK.finditer(line):
            target = m.group(1)
            if re.match(r"^[a-zA-Z][a-zA-Z0-9+.-]*:", target):
                continue  # a URL (http:, https:, mailto:, ...)
            file_part, _, anchor = target.partition("#")
            if file_part:
                dest = os.path.normpath(os.path.join(os.path.dirname(path), file_part))
            else:
                dest = path
            where = "%s:%d: (%s)" % (rel, number, target)
            if os.path.relpath(dest, repo).startswith(".."):
                problems.append("%s points outside the repository" % where)
            elif not os.path.exists(dest):
                problems.append("%s: no such file %s" % (where, os.path.relpath(dest, repo)))
            elif anchor and dest.endswith(".md") and anchor not in anchors(dest):
                problems.append("%s: %s has no heading with the anchor #%s"
                                % (where, os.path.relpath(dest, repo), anchor))
    return problems


def main(argv):
    if len(argv) < 2:
        print(__doc__)
        return 2
    repo = os.path.abspath(argv[1])
    files = argv[2:] or (["README.md"] + sorted(
        os.path.relpath(p, repo) for p in glob.glob(os.path.join(repo, "docs", "*.md"))))
    problems, count = [], 0
    for rel in files:
        found = check(repo, rel)
        problems += found
        with open(os.path.join(repo, rel), encoding="utf-8") as f:
            count += len(LINK.findall("\n".join(strip_code(f.read().split("\n")))))
    for p in problems:
        print("FAIL: " + p)
    print("%d files, %d links, %d dead" % (len(files), count, len(problems)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

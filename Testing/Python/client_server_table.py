"""Prints the table of client_server_loop_check.py's checks (plain python3): one row per
check, one column per run that compared itself with the built-in one (DIR/rows_*.json:
pvserver_N, pvbatch_N), "equal" or "DIFFERENT" and the run's detail for the picture.

  python3 client_server_table.py DIR"""
import glob
import json
import os
import re
import sys


def main():
    out = sys.argv[1]
    runs = []
    for path in glob.glob(os.path.join(out, "rows_*.json")):
        label = os.path.basename(path)[len("rows_"):-len(".json")]
        kind, n = re.match(r"(\w+?)_(\d+)$", label).groups()
        with open(path) as f:
            runs.append(((kind, int(n)), "%s %s" % (kind, n), json.load(f)))
    if not runs:
        print("client_server_table.py: no rows_*.json in %s" % out)
        return 1
    runs.sort()
    names = []
    for _, _, rows in runs:
        for name, _, _ in rows:
            if name not in names:
                names.append(name)
    print("| check | built-in | %s |" % " | ".join(label for _, label, _ in runs))
    print("|---|---|%s" % ("---|" * len(runs)))
    failed = 0
    for name in names:
        cells = []
        for _, _, rows in runs:
            found = [(ok, detail) for n, ok, detail in rows if n == name]
            if not found:
                cells.append("-")
                continue
            ok, detail = found[0]
            failed += not ok
            cell = "equal" if ok else "DIFFERENT"
            if name == "picture":
                cell += " (%s)" % detail
            cells.append(cell)
        print("| %s | reference | %s |" % (name, " | ".join(cells)))
    return 1 if failed else 0


sys.exit(main())

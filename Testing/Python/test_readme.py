"""Every ```python block of README.md and of the pages docs/user-guide.md (when it
exists), docs/reference.md and docs/gui.md is a whole script that runs as written: each block
is written to a file and run with pvbatch (through run_pvbatch.sh, under its own X
server) from a scratch copy of the paths it uses: the repository root's build/ plugin
path and .cache/volumes/ are replaced by MCV_PLUGIN and MCV_DATA_DIR when the tests run
from another build folder. Checks: exit status 0, no Python traceback, and the pictures
the block saves are written and not blank."""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

C = T.Checker("test_readme")
PAGES = ["README.md", "docs/user-guide.md", "docs/reference.md", "docs/gui.md"]
blocks = []  # (page, number on the page, script)
for page in PAGES:
    path = os.path.join(T.REPO, page)
    if not os.path.exists(path):
        C.check(page == "docs/user-guide.md", "%s exists" % page)
        continue
    found = re.findall(r"```python\n(.*?)```", open(path).read(), re.S)
    print("%s: %d python blocks" % (page, len(found)))
    blocks += [(page, number, block) for number, block in enumerate(found, 1)]
C.check(sum(1 for b in blocks if b[0] == "README.md") >= 1,
        "README has its python block")
C.check(sum(1 for b in blocks if b[0] == "docs/reference.md") >= 4,
        "docs/reference.md has its python blocks")
for name in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz"):
    T.data_file(name)

work = os.path.join(T.output_dir(), "readme")
os.makedirs(work, exist_ok=True)
plugin = os.environ.get("MCV_PLUGIN")
for index, (page, number, block) in enumerate(blocks, 1):
    name = "%s block %d" % (page, number)
    script = block
    if plugin:
        script = script.replace(
            "build/lib/paraview-5.11/plugins/MultichannelExplorer/MultichannelExplorer.so", plugin)
    script = script.replace(".cache/volumes/", T.data_dir().rstrip("/") + "/")
    path = os.path.join(work, "block%d.py" % index)
    with open(path, "w") as f:
        f.write(script)
    saved = re.findall(r'SaveScreenshot\("([^"]+)"', block)
    for picture in saved:
        if os.path.exists(os.path.join(work, picture)):
            os.remove(os.path.join(work, picture))
    run = T.run_pvbatch("pvbatch", [path], cwd=work, timeout=900)
    print("--- %s (%s):\n%s" % (name, path, run.stdout[-2500:]))
    C.check(run.returncode == 0 and "Traceback" not in run.stdout,
            "%s runs as written (exit %d)" % (name, run.returncode))
    for picture in saved:
        target = os.path.join(work, picture)
        C.check(os.path.exists(target) and os.path.getsize(target) > 5000,
                "%s wrote %s" % (name, picture))
C.finish()

"""Every ```python block of README.md is a whole script that runs as written: each block
is written to a file and run with pvbatch (through run_pvbatch.sh, under its own X
server) from a scratch copy of the paths it uses: the repository root's build/ plugin
path and .cache/volumes/ are replaced by MCV_PLUGIN and MCV_DATA_DIR when the tests run
from another build folder. Checks: exit status 0, no Python traceback, and the pictures
the block saves are written and not blank."""
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

C = T.Checker("test_readme")
readme = open(os.path.join(T.REPO, "README.md")).read()
blocks = re.findall(r"```python\n(.*?)```", readme, re.S)
C.check(len(blocks) >= 2, "README has its python blocks (%d)" % len(blocks))
for name in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz"):
    T.data_file(name)

work = os.path.join(T.output_dir(), "readme")
os.makedirs(work, exist_ok=True)
plugin = os.environ.get("MCV_PLUGIN")
for number, block in enumerate(blocks, 1):
    script = block
    if plugin:
        script = script.replace(
            "build/lib/paraview-5.11/plugins/MultichannelExplorer/MultichannelExplorer.so", plugin)
    script = script.replace(".cache/volumes/", T.data_dir().rstrip("/") + "/")
    path = os.path.join(work, "block%d.py" % number)
    with open(path, "w") as f:
        f.write(script)
    saved = re.findall(r'SaveScreenshot\("([^"]+)"', block)
    for picture in saved:
        if os.path.exists(os.path.join(work, picture)):
            os.remove(os.path.join(work, picture))
    run = subprocess.run(["sh", os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                             "run_pvbatch.sh"), "pvbatch", path],
                         cwd=work, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         universal_newlines=True, timeout=900)
    print("--- block %d:\n%s" % (number, run.stdout[-2500:]))
    C.check(run.returncode == 0 and "Traceback" not in run.stdout,
            "README python block %d runs as written (exit %d)" % (number, run.returncode))
    for picture in saved:
        target = os.path.join(work, picture)
        C.check(os.path.exists(target) and os.path.getsize(target) > 5000,
                "block %d wrote %s" % (number, picture))
C.finish()

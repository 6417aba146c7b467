"""Every example in the docstrings of the Python package multichannel_explorer (a ``::``
block) runs as written, in one pvbatch session, in the order of the package's files, with
the names the examples take as given defined once below on the real brain (Colin27 T1 +
AAL + Brodmann): volume, next_volume / other_volume, view, reduction, display, widgets,
domain. The working folder holds the brain's files under the names the examples use, so
"ch2.nii.gz" and "brain.mcvmodel" resolve there; the example's LoadPlugin path is the
built plugin's. A block that is no Python (a file format shown in a docstring, such as the
JSON of a transfer-function file) is named and skipped. Checks: no exception in any block; the examples that print show values."""
import ast
import glob
import io
import os
import re
import sys
import textwrap
import traceback
from contextlib import redirect_stdout

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

mce = T.load_plugin(globals())
from paraview import simple  # noqa: E402

C = T.Checker("test_docstrings")
# The package as the plugin embeds it, read from its sources.
PACKAGE = os.path.join(T.REPO, "Plugin", "MultichannelExplorer", "multichannel_explorer")
work = os.path.join(T.output_dir(), "docstrings")
os.makedirs(work, exist_ok=True)
for name in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz"):
    target = os.path.join(work, name)
    if not os.path.exists(target):
        os.symlink(T.data_file(name), target)
os.chdir(work)


def examples():
    """(file, function, code) of every :: block of the package's docstrings."""
    found = []
    for path in sorted(glob.glob(os.path.join(PACKAGE, "*.py"))):
        tree = ast.parse(open(path).read())
        for node in [tree] + [n for n in ast.walk(tree)
                              if isinstance(n, (ast.FunctionDef, ast.ClassDef))]:
            doc = ast.get_docstring(node, clean=True) or ""
            for m in re.finditer(r"::\n\n((?:[ ]{4}.*\n|\n)+)", doc + "\n"):
                found.append((os.path.basename(path), getattr(node, "name", "module"),
                              textwrap.dedent(m.group(1)).strip() + "\n"))
    return found


# The names the examples take as given.
readers = [simple.OpenDataFile(n) for n in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")]
volume = simple.MergeChannels(Input=readers)
next_volume = other_volume = simple.MergeChannels(
    Input=[simple.OpenDataFile(n) for n in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")])
view = simple.GetActiveViewOrCreate("RenderView")
view.ViewSize = [400, 300]
_, reduction = mce.reduce_multichannel(volume, "PCA", "6D", ReferenceSampleSize=3000)
display = mce.show_gaussian_tf(reduction, view)
widgets = list(mce.auto_widgets(display, 3))
domain = mce.reduced_domain_filter(reduction, SampleSize=2000)
domain.UpdatePipeline()
simple.SelectIDs(IDs=[0, 10, 0, 11, 0, 12], FieldType="POINT", Source=domain)  # a rubber band
# The files the examples read: a model and a transfer-function file of the reduction.
mce.save_model(reduction, "brain.mcvmodel")
mce.save_transfer_function(display, "brain.mcvtf")
namespace = dict(globals())

found = examples()
C.check(len(found) >= 12, "%d docstring examples found" % len(found))
ran = 0
for file, function, code in found:
    where = "%s %s" % (file, function)
    try:
        compiled = compile(code, where, "exec")
    except SyntaxError:
        compiled = None
    if compiled is None or code.lstrip().startswith("{"):
        print("skip %s: not Python (%s...)" % (where, code.splitlines()[0][:40]))
        continue
    code = code.replace("/path/to/MultichannelExplorer.so", os.environ.get("MCV_PLUGIN", ""))
    compiled = compile(code, where, "exec")
    printed = io.StringIO()
    try:
        with redirect_stdout(printed):
            exec(compiled, namespace)
        ok, why = True, ""
    except Exception:
        ok, why = False, traceback.format_exc(limit=3)
    text = printed.getvalue().strip()
    C.check(ok and ("print(" not in code or text),
            "%s runs%s%s" % (where, (": prints " + text.replace("\n", " | ")[:160]) if text else "",
                             ("\n" + why) if why else ""))
    ran += 1
C.check(ran >= 12, "%d examples ran" % ran)
C.finish()

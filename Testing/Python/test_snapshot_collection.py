"""Examples/snapshot_collection.py on a folder of the real volumes.

The folder holds the fetched volumes as they are (Colin27 ch2.nii.gz, brainsmall.den, the
4D diffusion volume small_64D.nii), conversions of real volumes written here with
ParaView/VTK writers (ch2 at half resolution as .vti, the AAL atlas as .mhd/.raw,
brainsmall as a stack of 2D TIFF slices), broken files of every format: a gzip-of-text .nii.gz, ch2.nii.gz cut inside its gzip stream, brainsmall.den
cut to half, ch2 as .mhd/.raw with the .raw cut, ch2 as a multi-page TIFF cut to half,
and random bytes named .nii, .den, .mhd and .tif; and one file that is no volume. Checks:
the index (HTML + JSON), a non-blank thumbnail and a unit best direction for every good
volume, an error entry with its reason (in index.json and index.html) and no thumbnail for
every broken one while the others succeed, a second run that skips everything and is
fast, --force NAME redoing one volume, a lost record redone on resume, and --timeout
turning a too-slow volume into an error entry.
"""
import gzip
import html
import json
import os
import random
import re
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402

mce = T.load_plugin(globals())
checker = T.Checker("test_snapshot_collection")
SCRIPT = os.path.join(T.REPO, "Examples", "snapshot_collection.py")
PVBATCH = os.path.realpath("/proc/self/exe")  # this pvbatch (sys.executable is not it)

ch2 = T.data_file("ch2.nii.gz")
aal = T.data_file("aal.nii.gz")
den = T.data_file("brainsmall.den")
dwi = T.data_file("small_64D.nii")

work = os.path.join(T.output_dir(), "snapshot_collection")
shutil.rmtree(work, ignore_errors=True)
inp = os.path.join(work, "input")
out = os.path.join(work, "index")
os.makedirs(os.path.join(inp, "brainsmall_tiff"))

# Real volumes as fetched.
for f in (ch2, den, dwi):
    shutil.copy(f, inp)

# Conversions written with ParaView's writers (and VTK's TIFF writer for 2D slices).
ch2_reader = simple.OpenDataFile(ch2)
ch2_reader.UpdatePipeline()  # ExtractSubset's VOI must see the whole extent
half = simple.ExtractSubset(Input=ch2_reader, VOI=[0, 180, 0, 216, 0, 180],
                            SampleRateI=2, SampleRateJ=2, SampleRateK=2)
half.UpdatePipeline()  # else SaveData writes an empty piece
# Inline binary: Debian 12's ParaView cannot read back raw appended .vti data (its XML
# parser stops at the raw bytes: "junk after document element").
simple.SaveData(os.path.join(inp, "ch2_half.vti"), proxy=half, DataMode="Binary",
                CompressorType="ZLib")
simple.SaveData(os.path.join(inp, "aal.mhd"), proxy=simple.OpenDataFile(aal))
den_reader = simple.OpenDataFile(den)
den_reader.UpdatePipeline()
from vtkmodules.vtkIOImage import vtkTIFFWriter  # noqa: E402

# One 2D TIFF per slice.
den_image = den_reader.GetClientSideObject().GetOutputDataObject(0)
T.write_tiff_stack(den_image, os.path.join(inp, "brainsmall_tiff"))
n_slices = len([f for f in os.listdir(os.path.join(inp, "brainsmall_tiff"))
                if f.endswith(".tif")])
checker.check(n_slices == 84, "TIFF stack written: %d slices of brainsmall" % n_slices)
checker.check(os.path.exists(os.path.join(inp, "aal.raw")) or
              os.path.exists(os.path.join(inp, "aal.zraw")),
              "MetaImage written as .mhd + raw data file")

# The T1 as float with a long bright tail (every 997th head voxel at 10x the maximum, as
# vessels or artefacts can be): the default ramp must still show the anatomy.
import numpy as np  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter  # noqa: E402

ch2_image = ch2_reader.GetClientSideObject().GetOutputDataObject(0)
t1 = vtk_to_numpy(ch2_image.GetPointData().GetScalars()).astype(np.float32)
head = np.flatnonzero(t1 > t1.min())
t1[head[::997]] = 10 * t1.max()
tail_image = vtkImageData()
tail_image.CopyStructure(ch2_image)
tail_array = numpy_to_vtk(t1, deep=1)
tail_array.SetName("T1")
tail_image.GetPointData().SetScalars(tail_array)
tail_writer = vtkXMLImageDataWriter()
tail_writer.SetInputData(tail_image)
tail_writer.SetDataModeToBinary()
tail_writer.SetFileName(os.path.join(inp, "ch2_bright_tail.vti"))
tail_writer.Write()

# Broken volumes: a gzip of text named like NIfTI, cut copies of the real volumes in each
# format, random bytes under each extension; and a file that is no volume.
with gzip.open(os.path.join(inp, "corrupt.nii.gz"), "wb") as f:
    f.write(b"this is not a NIfTI header " * 40)
with open(os.path.join(inp, "README.txt"), "w") as f:
    f.write("not a volume\n")


def cut_copy(source, name, fraction=0.5):
    with open(source, "rb") as f:
        data = f.read()
    with open(os.path.join(inp, name), "wb") as f:
        f.write(data[:int(len(data) * fraction)])


from vtkmodules.vtkIOImage import vtkMetaImageWriter  # noqa: E402

scratch = os.path.join(work, "scratch")
os.makedirs(scratch)
cut_copy(ch2, "cut_ch2.nii.gz")
cut_copy(den, "cut_brainsmall.den")
ch2_image = ch2_reader.GetClientSideObject().GetOutputDataObject(0)
mhd_writer = vtkMetaImageWriter()
mhd_writer.SetInputData(ch2_image)
mhd_writer.SetCompression(False)
mhd_writer.SetFileName(os.path.join(inp, "cut_ch2.mhd"))
mhd_writer.SetRAWFileName(os.path.join(inp, "cut_ch2.raw"))
mhd_writer.Write()
cut_copy(os.path.join(inp, "cut_ch2.raw"), "cut_ch2.raw")
tiff = vtkTIFFWriter()
tiff.SetInputData(ch2_image)
tiff.SetFileName(os.path.join(scratch, "ch2_pages.tif"))
tiff.Write()
cut_copy(os.path.join(scratch, "ch2_pages.tif"), "cut_ch2.tif")
noise = random.Random(19)
for ext in (".nii", ".den", ".mhd", ".tif"):
    with open(os.path.join(inp, "random" + ext), "wb") as f:
        f.write(bytes(noise.getrandbits(8) for _ in range(100000)))

GOOD = {  # name in the index -> (dimensions, components)
    "ch2.nii.gz": ([181, 217, 181], 1),
    "ch2_half.vti": ([91, 109, 91], 1),
    "ch2_bright_tail.vti": ([181, 217, 181], 1),
    "aal.mhd": ([181, 217, 181], 1),
    "brainsmall.den": ([128, 128, 84], 1),
    os.path.join("brainsmall_tiff", "slice_*.tif"): ([128, 128, 84], 1),
    "small_64D.nii": ([10, 10, 10], 65),
}
BROKEN = {  # name in the index -> words its error must hold (the reason)
    "corrupt.nii.gz": ["no reader accepts this file", "corrupt or not a volume"],
    "cut_ch2.nii.gz": ["cut_ch2.nii.gz", "not a complete gzip stream"],
    "cut_brainsmall.den": ["cut_brainsmall.den", "truncated", "1376256 voxels"],
    "cut_ch2.mhd": ["cut_ch2.raw", "truncated", "promises 7109137 bytes"],
    "cut_ch2.tif": ["cut_ch2.tif", "truncated", "directory of page"],
    "random.nii": ["no reader accepts this file", "random.nii"],
    "random.den": ["no reader accepts this file", "random.den"],
    "random.mhd": ["no reader accepts this file", "random.mhd"],
    "random.tif": ["no reader accepts this file", "random.tif"],
}
env = dict(os.environ)


def run(*extra):
    cmd = [PVBATCH, SCRIPT, "--input", inp, "--output", out] + list(extra)
    if os.environ.get("MCV_PLUGIN"):
        cmd += ["--plugin", os.environ["MCV_PLUGIN"]]
    start = time.time()
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          universal_newlines=True, env=env)
    elapsed = time.time() - start
    print("---- snapshot_collection %s: exit %d, %.1f s" % (" ".join(extra), proc.returncode,
                                                          elapsed))
    print(proc.stdout)
    sys.stdout.flush()
    return proc, elapsed


def load_index():
    with open(os.path.join(out, "index.json")) as f:
        return {r["name"]: r for r in json.load(f)["volumes"]}


def mtimes():
    return {name: os.stat(os.path.join(out, "records", r["id"] + ".json")).st_mtime_ns
            for name, r in load_index().items()}


# 1. First run: every volume processed.
proc, first_time = run()
total = len(GOOD) + len(BROKEN)
checker.check(proc.returncode == 0, "first run exits 0 (rc %d)" % proc.returncode)
checker.check("%d of %d volumes succeeded" % (len(GOOD), total) in proc.stdout,
              "summary says %d of %d volumes succeeded" % (len(GOOD), total))
bars = re.findall(r"^\[([# ]{20})\] (\d+)/(\d+) (\S+)", proc.stdout, re.M)
checker.check(len(bars) == total and bars[-1][0] == "#" * 20 and bars[-1][1:3] == (
    str(total), str(total)), "a progress bar line per volume, full at the end (%d lines)"
    % len(bars))
checker.check(os.path.exists(os.path.join(out, "index.html")) and
              os.path.exists(os.path.join(out, "index.json")), "index.html and index.json")
index = load_index()
checker.check(sorted(index) == sorted(list(GOOD) + list(BROKEN)),
              "the index lists exactly the volumes (README.txt and the .raw files ignored): %s"
              % sorted(index))
with open(os.path.join(out, "index.html")) as f:
    page = f.read()

for name, (dims, ncomp) in sorted(GOOD.items()):
    r = index.get(name)
    if not checker.check(r is not None and r["status"] == "ok",
                         "%s: succeeded (%s)" % (name, r and r.get("error"))):
        continue
    checker.check(r["dimensions"] == dims and r["components"] == ncomp,
                  "%s: dimensions %s, %d component(s)" % (name, r["dimensions"],
                                                          r["components"]))
    d = r["best_direction"]
    checker.check(T.all_finite(d) and abs(T.norm(d) - 1.0) < 1e-3,
                  "%s: unit best direction %s" % (name, d))
    eig = r["eigenvalues"]
    checker.check(len(eig) == 3 and abs(sum(eig) - 1.0) < 1e-3 and eig[0] >= eig[1] >= eig[2] >= 0,
                  "%s: eigenvalue spectrum %s descending, sum 1" % (name, eig))
    checker.check(r["range"][1] > r["range"][0] and len(r["spacing"]) == 3 and r["scalar_type"],
                  "%s: %s, range %s, spacing %s" % (name, r["scalar_type"], r["range"],
                                                    r["spacing"]))
    T.image_ok(mce, os.path.join(out, r["thumbnail"]), checker, name)
    ramp = r.get("ramp", [None, None])
    checker.check(ramp[0] is not None and r["range"][0] <= ramp[0] < ramp[1] <= r["range"][1],
                  "%s: default ramp %s within the range %s" % (name, ramp, r["range"]))

# The bright tail: the ramp ends at the tissue, not at the tail, and the thumbnail shows
# the anatomy about as the plain T1's does.
tail, plain = index.get("ch2_bright_tail.vti"), index.get("ch2.nii.gz")
if tail and plain and tail.get("status") == plain.get("status") == "ok":
    tail_stats = mce.image_statistics(os.path.join(out, tail["thumbnail"]))
    plain_stats = mce.image_statistics(os.path.join(out, plain["thumbnail"]))
    print("bright tail: ramp %s of range %s; thumbnail %s; plain T1 %s"
          % (tail["ramp"], tail["range"], tail_stats, plain_stats))
    checker.check(tail["ramp"][1] < 0.2 * tail["range"][1],
                  "bright tail: the ramp ends below a fifth of the maximum (%s of %s)"
                  % (tail["ramp"][1], tail["range"][1]))
    checker.check(tail_stats["non_background_fraction"] >
                  0.7 * plain_stats["non_background_fraction"] and
                  tail_stats["stddev"] > 0.5 * plain_stats["stddev"],
                  "bright tail: the thumbnail shows the anatomy like the plain T1's")
    checker.check(('src="%s"' % r["thumbnail"]) in page and name in page,
                  "%s: thumbnail and name in index.html" % name)
checker.check(index["ch2_half.vti"]["spacing"] == [2.0, 2.0, 2.0],
              "the half-resolution .vti keeps its world spacing (2 mm)")
# The same brain read from .den and from the TIFF stack: the TIFF round trip mirrors y
# (TIFF rows run top-down, VTK's bottom-up), so the best axis must be the mirrored one.
a = index["brainsmall.den"].get("best_direction")
b = index[os.path.join("brainsmall_tiff", "slice_*.tif")].get("best_direction")
if a and b:
    mirrored = [a[0], -a[1], a[2]]
    checker.check(T.angle_deg(mirrored, b, unsigned=True) < 5.0,
                  "brainsmall .den and TIFF stack: same best axis up to the y mirror "
                  "(%.2f deg apart; %.1f deg unmirrored)"
                  % (T.angle_deg(mirrored, b, unsigned=True), T.angle_deg(a, b, unsigned=True)))

for name, words in sorted(BROKEN.items()):
    bad = index.get(name, {})
    error = bad.get("error", "")
    checker.check(bad.get("status") == "error" and "thumbnail" not in bad and
                  all(w.lower() in error.lower() for w in words),
                  "%s: an error entry with its reason (%s): '%s', no thumbnail"
                  % (name, words, error))
    checker.check(error and html.escape(error) in page, "%s: its error text in index.html" % name)

# 2. Second run: everything skipped, nothing rewritten, fast.
before = mtimes()
proc, second_time = run()
checker.check(proc.returncode == 0 and "%d processed, %d skipped" % (0, total) in proc.stdout,
              "second run: 0 processed, %d skipped" % total)
checker.check(mtimes() == before, "second run rewrote no record")
checker.check(second_time < 15.0 and second_time < 0.5 * first_time,
              "second run fast: %.1f s (first %.1f s)" % (second_time, first_time))

# 3. --force NAME redoes that volume only.
proc, _ = run("--force", "brainsmall.den")
after = mtimes()
changed = sorted(n for n in after if after[n] != before[n])
checker.check(proc.returncode == 0 and changed == ["brainsmall.den"] and
              "1 processed, %d skipped" % (total - 1) in proc.stdout,
              "--force brainsmall.den redoes only it (changed: %s)" % changed)
checker.check(load_index()["brainsmall.den"]["status"] == "ok", "forced volume succeeded again")

# 4. Resume: a volume whose record is missing (a run stopped while it was being
#    rendered) is redone, the others are skipped.
os.remove(os.path.join(out, "records", index["ch2_half.vti"]["id"] + ".json"))
proc, _ = run()
checker.check(proc.returncode == 0 and "1 processed, %d skipped" % (total - 1) in proc.stdout
              and load_index()["ch2_half.vti"]["status"] == "ok",
              "resume: the volume without a record is redone, the rest skipped")

# 4b. Resume at another --size: the volume is rendered again at that size, then reused.
sized_in, sized_out = os.path.join(work, "sized"), os.path.join(work, "sized_index")
os.makedirs(sized_in)
shutil.copy(den, sized_in)


def sized_run(*extra):
    cmd = [PVBATCH, SCRIPT, "--input", sized_in, "--output", sized_out] + list(extra)
    if os.environ.get("MCV_PLUGIN"):
        cmd += ["--plugin", os.environ["MCV_PLUGIN"]]
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          universal_newlines=True, env=env)
    thumbnail = os.path.join(sized_out, "thumbnails", "brainsmall.den.png")
    return proc, mce.image_statistics(thumbnail)["pixels"] if os.path.exists(thumbnail) else 0


first, _ = sized_run()
again, pixels = sized_run("--size", "160", "120")
same, _ = sized_run("--size", "160", "120")
checker.check(first.returncode == 0 and again.returncode == 0 and
              "1 processed, 0 skipped" in again.stdout and pixels == 160 * 120 and
              "0 processed, 1 skipped" in same.stdout,
              "resume with another --size renders the volume again at 160 x 120 (%d pixels), "
              "then reuses it" % pixels)

# 5. A volume over the time limit becomes an error entry; no success -> exit code 1.
slow_in = os.path.join(work, "slow")
os.makedirs(slow_in)
shutil.copy(den, slow_in)
cmd = [PVBATCH, SCRIPT, "--input", slow_in, "--output", os.path.join(work, "slow_index"),
       "--timeout", "0.5"]
proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                      universal_newlines=True, env=env)
print(proc.stdout)
with open(os.path.join(work, "slow_index", "index.json")) as f:
    slow = json.load(f)["volumes"][0]
checker.check(proc.returncode == 1 and "0 of 1 volumes succeeded" in proc.stdout and
              "timed out" in slow.get("error", ""),
              "--timeout 0.5: error entry '%s', exit code %d" % (slow.get("error"),
                                                                 proc.returncode))
checker.finish()

"""Atlas (label) channels told from images on the real volumes, and the widget names they
give. Colin27 T1 (ch2: uint8, 249 distinct integers), AAL (116 labels + 0) and Brodmann
(41 labels + 0), 181 x 217 x 181 on one grid. Known answers:
- label_channels on 20000 real voxels (evenly spread over the T1's non-zero voxels) with
  their next voxels along x: AAL and Brodmann are label channels, ch2 is not (the share
  of voxel pairs keeping their value: about 0.1 for ch2, about 0.9 for the atlases);
  without the neighbours only the count of distinct integers is left, which calls AAL
  (117 values in the sample) an intensity: the case the neighbours fix;
- widget_names on real voxels of known regions (widget 1: AAL label 1, widget 2: AAL
  label 2, widget 3: voxels outside both atlases with the brightest T1): with the AAL
  label table from the reader (aal.nii.txt) "Precentral_L", "Precentral_R", "ch2 bright";
  without a table "aal 1", "aal 2", "ch2 bright" (never "aal mid ...");
- the GUI's case: the three files without aal.nii.txt beside them -> MergeChannels ->
  DimensionReduction (defaults) -> auto_widgets(5): the reduced domain's sample and its
  neighbours (what auto_widgets reads) give AAL and Brodmann as label channels and ch2 as
  an intensity; no widget is named after AAL or Brodmann as if they were intensities
  ("aal mid ~0", "aal bright ~51" before);
- the region borders auto_widgets reads (a sampled voxel with a face neighbour of another
  label, read through ExtractVoxels) equal numpy's on the whole volume, and a widget named
  "<atlas> boundaries" has at least BOUNDARY_SHARE of its sampled voxels on them.
"""
import os
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import servermanager, simple  # noqa: E402
import numpy as np  # noqa: E402

mce = T.load_plugin(globals())
from multichannel_explorer import seeding  # noqa: E402
from multichannel_explorer._voxels import label_tables  # noqa: E402

C = T.Checker("test_atlas_labels")
table_file = T.data_file("aal.nii.txt")  # SKIP without it (scripts/fetch-data.sh)
brain = T.brain_arrays()  # (channel, z, y, x): ch2, aal, brodmann
ch2, aal, brodmann = brain
nz, ny, nx = ch2.shape
flat = {name: brain[c].reshape(-1) for c, name in enumerate(T.BRAIN)}

# ---- label_channels on real voxels -------------------------------------------------------
inside = np.nonzero(flat["ch2"] != 0)[0]
ids = inside[np.linspace(0, len(inside) - 1, 20000).astype(np.int64)]
after = np.where(ids % nx < nx - 1, ids + 1, ids - 1)  # the next voxel along x (as auto_widgets)
columns = {name: [(float(v),) for v in flat[name][ids]] for name in T.BRAIN}
columns["VoxelId"] = [(float(i),) for i in ids]
neighbours = {name: [float(v) for v in flat[name][after]] for name in T.BRAIN}
for name in T.BRAIN:
    a, b = flat[name][ids], flat[name][after]
    pair = (a != 0) | (b != 0)
    print("%-8s distinct %3d, voxel pairs keeping their value %.3f"
          % (name, len(np.unique(a)), float(((a == b) & pair).sum()) / pair.sum()))
found = seeding.label_channels(columns, {}, neighbours)
C.check(found == ["aal", "brodmann"],
        "label_channels on 20000 real voxels with their neighbours: %s (ch2 an intensity)"
        % found)
without = seeding.label_channels(columns, {}, None)
C.check("aal" not in without and "brodmann" in without and "ch2" not in without,
        "without neighbours only the distinct-integer count is left: %s (AAL's %d values "
        "pass for an intensity)" % (without, len(np.unique(flat["aal"][ids]))))
C.check(seeding.label_channels(columns, {"aal": {1: "Precentral_L"}}, None) == ["aal", "brodmann"],
        "a label table makes its channel an atlas whatever its values")

# ---- widget_names on voxels of known regions ---------------------------------------------
reader = simple.NIfTIImageReader(FileName=T.data_file("aal.nii.gz"))
tables = label_tables(servermanager.Fetch(reader))
simple.Delete(reader)
C.check(tables.get("aal", {}).get(1) == "Precentral_L" and tables["aal"].get(2) == "Precentral_R"
        and len(tables["aal"]) == 116,
        "the reader's AAL label table (aal.nii.txt): %d labels, 1 = %s"
        % (len(tables.get("aal", {})), tables.get("aal", {}).get(1)))
outside = np.nonzero((flat["aal"] == 0) & (flat["brodmann"] == 0) & (flat["ch2"] != 0))[0]
bright = outside[np.argsort(flat["ch2"][outside], kind="stable")[-300:]]
groups = [np.nonzero(flat["aal"] == 1)[0][:300], np.nonzero(flat["aal"] == 2)[0][:300], bright]
rest = ids[:3000]  # the rest of the sample: the widgets' surroundings
chosen = np.concatenate(groups + [rest])
sample = {name: [(float(v),) for v in flat[name][chosen]] for name in T.BRAIN}
sample["SeededWidget"] = [(float(w),) for w, g in enumerate(groups) for _ in g] + \
    [(3.0,)] * len(rest)
after = np.where(chosen % nx < nx - 1, chosen + 1, chosen - 1)
near = {name: [float(v) for v in flat[name][after]] for name in T.BRAIN}
named = seeding.widget_names(sample, 3, tables, near)
C.check(named == ["Precentral_L", "Precentral_R", "ch2 bright"],
        "widget names with the AAL table: %s" % named)
named = seeding.widget_names(sample, 3, {}, near)
C.check(named == ["aal 1", "aal 2", "ch2 bright"],
        "widget names without a table, AAL told a label channel by its neighbours: %s" % named)

# ---- the GUI's case: no label file beside the atlas ----------------------------------------
folder = tempfile.mkdtemp(prefix="atlas_labels_")
for name in T.BRAIN:
    os.symlink(T.data_file(name + ".nii.gz"), os.path.join(folder, name + ".nii.gz"))
readers = [simple.OpenDataFile(os.path.join(folder, n + ".nii.gz")) for n in T.BRAIN]
merged = simple.MergeChannels(Input=readers)
reduction = simple.DimensionReduction(Input=simple.MultichannelFeatures(Input=merged))
reduction.UpdatePipeline()
view = simple.CreateRenderView()
view.ViewSize = [300, 300]
display = mce.show_gaussian_tf(reduction, view)
seen = {}
names_of = seeding.widget_names


def recording(columns, count, tables, neighbours=None, boundaries=None):
    seen.update(tables=tables, atlases=seeding.label_channels(columns, tables, neighbours),
                read=sum(1 for v in (neighbours or {}).get("aal", []) if v is not None),
                columns=columns, boundaries=boundaries)
    return names_of(columns, count, tables, neighbours, boundaries)


seeding.widget_names = recording
mce.auto_widgets(display, 5)
seeding.widget_names = names_of
names = [str(n) for n in display.GaussianWidgetNames]
C.check(seen.get("tables") == {} and seen.get("atlases") == ["aal", "brodmann"] and
        seen.get("read", 0) >= 1000,
        "auto_widgets without label files: %d neighbours read, label channels %s"
        % (seen.get("read", 0), seen.get("atlases")))
C.check(len(names) == 5 and all(names) and not any(
    n.startswith(("aal ", "brodmann ")) and n.split()[1] in ("mid", "bright", "dark")
    for n in names), "no widget named after an atlas as an intensity: %s" % names)

# The region borders auto_widgets read (ExtractVoxels of the face neighbours) against numpy's
# on the whole volume: a voxel is on a border when a face neighbour inside the grid holds
# another value.
def on_border(labels):
    border = np.zeros(labels.shape, dtype=bool)
    for axis in range(3):
        ahead = [slice(None)] * 3
        behind = [slice(None)] * 3
        ahead[axis], behind[axis] = slice(1, None), slice(None, -1)
        differ = labels[tuple(ahead)] != labels[tuple(behind)]
        border[tuple(ahead)] |= differ
        border[tuple(behind)] |= differ
    return border.reshape(-1)


sampled = [int(v[0]) for v in seen["columns"]["VoxelId"]]
for name in ("aal", "brodmann"):
    truth = on_border(brain[T.BRAIN.index(name)])
    flags = seen["boundaries"][name]
    read = [(p, f) for p, f in enumerate(flags) if f is not None]
    wrong = sum(1 for p, f in read if f != bool(truth[sampled[p]]))
    C.check(len(read) >= 1000 and wrong == 0,
            "%s borders read at %d sampled voxels, %d differ from numpy's" % (name, len(read), wrong))
widget_of = [int(v[0]) for v in seen["columns"]["SeededWidget"]]
for w, n in enumerate(names):
    if n.split()[-1] == "boundaries" or n.split()[-2:-1] == ["boundaries"]:
        truth = on_border(brain[T.BRAIN.index(n.split()[0])])
        mine = [truth[sampled[p]] for p, x in enumerate(widget_of) if x == w]
        C.check(float(np.mean(mine)) >= seeding.BOUNDARY_SHARE,
                "widget %d '%s': %.0f %% of its sampled voxels on the atlas's borders (numpy)"
                % (w + 1, n, 100.0 * float(np.mean(mine))))
print("names:", names)
shutil.rmtree(folder, ignore_errors=True)  # the links only; the volumes stay
C.finish()

"""The Channels lists tell the truth, and atlas channels carry their label tables.

Known answers on the real brain (Colin27 T1 + AAL + Brodmann, MCV_DATA_DIR; aal.nii.txt
beside aal.nii.gz, fetched from mricron-data by scripts/fetch-data.sh as the volumes are):
- the NIfTI reader attaches the AAL label file as the field array aal_labels: one entry
  "<value>\\t<name>" per line of aal.nii.txt, in its order (116 labels, 1 = Precentral_L);
  ch2 and Brodmann (no .txt beside them) get none;
- MergeChannels keeps it with its channel; a second AAL file merged after it (channel
  aal_2) brings its table as aal_2_labels; MultichannelFeatures and DimensionReduction
  pass it on;
- the Channels lists (the domain the GUI's list shows) of MultichannelFeatures,
  DimensionReduction (after MultichannelFeatures: no Features, no Foreground) and
  BestViewpoint (after DimensionReduction: no ReducedCoordinates) are ch2, aal, brodmann
  (the domain's order, by name: aal, brodmann, ch2, the numbers #1-#3 of the GUI's
  list), and the properties hold all three in that order (all used);
- a label file with a line that is not "<value> <name>": a warning naming the file and
  the line, the volume read all the same, no table.
"""
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402

T.load_plugin(globals())
C = T.Checker("test_channel_list")
out = T.fresh_output_dir("channel_list")


label_file = T.data_file("aal.nii.txt")
expected = []
with open(label_file) as f:
    for line in f:
        fields = line.split()
        if fields:
            expected.append("%d\t%s" % (int(fields[0]), fields[1]))
C.check(len(expected) == 116 and expected[0] == "1\tPrecentral_L",
        "aal.nii.txt (mricron-data): 116 labels, the first 1 Precentral_L")

readers = [simple.OpenDataFile(T.data_file(f))
           for f in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz")]
tables = [T.field_strings(T.output_of(r), n + "_labels") for r, n in zip(readers, ("ch2", "aal", "brodmann"))]
C.check(tables[1] == expected, "the AAL reader's field array aal_labels is the file, line by "
        "line (%s entries)" % (len(tables[1]) if tables[1] else None))
C.check(tables[0] is None and tables[2] is None, "ch2 and Brodmann: no label table")

# A second AAL file (another folder): the merged channel aal_2 has its own table.
other = os.path.join(out, "other")
os.makedirs(other)
shutil.copyfile(T.data_file("aal.nii.gz"), os.path.join(other, "aal.nii.gz"))
shutil.copyfile(label_file, os.path.join(other, "aal.nii.txt"))
twice = simple.MergeChannels(Input=readers + [simple.OpenDataFile(os.path.join(other, "aal.nii.gz"))])
image = T.output_of(twice)
names = [image.GetPointData().GetArrayName(i) for i in range(image.GetPointData().GetNumberOfArrays())]
C.check(names == ["ch2", "aal", "brodmann", "aal_2"] and T.field_strings(image, "aal_labels") == expected
        and T.field_strings(image, "aal_2_labels") == expected,
        "merged with a second AAL: channels %s, tables aal_labels and aal_2_labels" % names)
simple.Delete(twice)

merged = simple.MergeChannels(Input=readers)
C.check(T.field_strings(T.output_of(merged), "aal_labels") == expected, "MergeChannels keeps aal_labels")


def domain_strings(proxy):
    """The channels the domain offers, in its order: the GUI's list numbers them so (#1,
    #2, ...), and the domain fills the property, hence the filters' order, the same way."""
    domain = proxy.GetProperty("Channels").SMProperty.FindDomain("vtkSMArrayListDomain")
    return [domain.GetString(i) for i in range(domain.GetNumberOfStrings())]


# ParaView's data information lists arrays by name: the domain's (and the filters') order.
IN_ORDER = ["aal", "brodmann", "ch2"]
OFFERED = IN_ORDER


features = simple.MultichannelFeatures(Input=merged)
C.check(domain_strings(features) == OFFERED and list(features.Channels) == IN_ORDER,
        "MultichannelFeatures' Channels list: %s, all used (%s)"
        % (domain_strings(features), list(features.Channels)))
features.UpdatePipeline()
reduction = simple.DimensionReduction(Input=features, ReferenceSampleSize=2000)
shown = domain_strings(reduction)
C.check(shown == OFFERED and list(reduction.Channels) == IN_ORDER,
        "DimensionReduction's Channels list after MultichannelFeatures: %s (no Features, no "
        "Foreground), all used, in that order %s" % (shown, list(reduction.Channels)))
reduced = T.output_of(reduction)
C.check(T.field_strings(reduced, "aal_labels") == expected,
        "the reduced volume still carries aal_labels (MultichannelFeatures and "
        "DimensionReduction pass it on)")
best = simple.BestViewpoint(Input=reduction)
C.check(domain_strings(best) == OFFERED and list(best.Channels) == IN_ORDER,
        "BestViewpoint's Channels list after DimensionReduction: %s (no ReducedCoordinates), "
        "property %s" % (domain_strings(best), list(best.Channels)))

# A bad label file: said, and the volume is read all the same.
bad = os.path.join(out, "bad")
os.makedirs(bad)
shutil.copyfile(T.data_file("aal.nii.gz"), os.path.join(bad, "aal.nii.gz"))
with open(os.path.join(bad, "aal.nii.txt"), "w") as f:
    f.write("1 Precentral_L 2001\nPrecentral_R 2 2002\n")
bad_reader = simple.OpenDataFile(os.path.join(bad, "aal.nii.gz"))
msgs = T.Messages(bad_reader)
data = T.output_of(bad_reader)
C.check(msgs.any_warning("aal.nii.txt", "line 2") and data.GetNumberOfPoints() == 181 * 217 * 181
        and T.field_strings(data, "aal_labels") is None,
        "a bad label file: a warning naming it and the line (%s), the volume read, no table"
        % msgs.warnings)
C.finish()

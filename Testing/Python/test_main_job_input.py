"""The main job (Examples/transfer_function.py) on one multichannel microscopy file:
--input FILE with an ImageJ hyperstack of the real 3-channel brain (Colin27 T1, AAL,
Brodmann, every 2nd voxel per axis, 2 um voxels) written here with tifffile.

Known answers: the job runs to the end; report.json names the file and counts its voxels
(91 x 109 x 91); best.png and dual_domain.png are written and not blank;
and the same job given the three channels as NIfTI files with --channels, on the same grid,
finds the same best direction (the chain's equality itself is test_tiff_chain's).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402

from paraview import simple  # noqa: E402

mce = T.load_plugin(globals())
C = T.Checker("test_main_job_input")
import numpy as np  # noqa: E402
import tifffile  # noqa: E402

work = os.path.join(T.output_dir(), "main_job_input")
os.makedirs(work, exist_ok=True)
channels = list(T.brain_arrays(T.BRAIN, step=2))
nifti = []
for n in T.BRAIN:
    # The same grid as separate files: every 2nd voxel, 2 mm apart, origin 0.
    reader = simple.OpenDataFile(T.data_file(n + ".nii.gz"))
    reader.UpdatePipeline()
    d = reader.GetDataInformation().GetExtent()
    sub = simple.ExtractSubset(Input=reader, VOI=list(d), SampleRateI=2, SampleRateJ=2,
                               SampleRateK=2)
    path = os.path.join(work, n + ".vti")
    sub.UpdatePipeline()
    simple.SaveData(path, proxy=sub, DataMode="Binary", CompressorType="ZLib")
    nifti.append(path)
stack = os.path.join(work, "brain_hyperstack.tif")
spacing = 2.0
tifffile.imwrite(stack, np.ascontiguousarray(np.stack(channels).transpose(1, 0, 2, 3)),
                 imagej=True, resolution=(1 / spacing, 1 / spacing),
                 metadata={"axes": "ZCYX", "spacing": spacing, "unit": "um"})


def job(output, *inputs):
    return T.run_example(C, "transfer_function.py", [
        "--features", "6D", "--method", "PCA", "--no-methods", "--widgets", "3",
        "--size", "400", "300", "--output", output] + list(inputs), output)


report = job(os.path.join(work, "from_hyperstack"), "--input", stack)
C.check(report["channels"] == [os.path.abspath(stack)], "report names the file: %s"
        % report["channels"])
C.check(report["voxels"] == 91 * 109 * 91, "report counts the file's voxels: %d"
        % report["voxels"])
for png in ("best.png", "dual_domain.png"):
    stats = mce.image_statistics(os.path.join(work, "from_hyperstack", png))
    C.check(stats["stddev"] > 5, "%s written and not blank (stddev %.1f)" % (png, stats["stddev"]))
# The same channels as separate files, on the same grid and spacing (.vti keeps 2 mm).
reference = job(os.path.join(work, "from_files"), "--channels", *nifti)


a, b = np.array(report["best_direction"]), np.array(reference["best_direction"])
C.check(abs(float(a @ b) - 1) < 1e-6,
        "same best direction from the hyperstack as from the files: %s vs %s" % (a, b))
C.finish()

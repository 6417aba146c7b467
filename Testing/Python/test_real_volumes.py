"""(a) Best viewpoint on real volumes: Colin27 ch2 (NIfTI) and VolPack's brainsmall.den.

For each volume: the readers give the expected grid; BestViewpoint runs, returns 2048
interest points with a float HarrisScore inside the volume, orthonormal directions and
eigenvalues that sum to 1; apply_best_viewpoint points the camera along the computed
direction (CameraFocalPoint - CameraPosition parallel to it, view-up = ViewUp, focal point
= volume centre); the best and worst screenshots are written and are not blank.
ch2 is also read with ParaView's own NIfTI reader (AnalyzeNIfTIReaderWriter plugin, on an
uncompressed copy): same grid, same direction.
"""
import gzip
import os
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402
import builtins as B  # noqa: E402  (ProgrammableSource scripts may shadow all/abs/... in __main__)

from paraview.simple import *  # noqa: E402,F401,F403

mce = T.load_plugin(globals())
C = T.Checker("test_real_volumes")
out = T.output_dir()


def check_filter(label, bvp, bounds):
    bvp.UpdatePipeline()
    bvp.UpdatePropertyInformation()
    best = [float(x) for x in bvp.GetPropertyValue("BestViewDirection")]
    worst = [float(x) for x in bvp.GetPropertyValue("WorstViewDirection")]
    up = [float(x) for x in bvp.GetPropertyValue("ViewUp")]
    eig = [float(x) for x in bvp.GetPropertyValue("EigenvalueSpectrum")]
    C.check(int(bvp.GetPropertyValue("ViewValid")) == 1, "%s: ViewValid" % label)
    C.check(T.all_finite(best + worst + up + eig), "%s: results finite" % label)
    C.check(B.all(B.abs(T.norm(v) - 1) < 1e-6 for v in (best, worst, up)),
            "%s: unit directions" % label)
    C.check(B.abs(T.dot(best, worst)) < 1e-6 and B.abs(T.dot(best, up)) < 1e-6
            and B.abs(T.dot(worst, up)) < 1e-6, "%s: orthogonal directions" % label)
    C.check(B.abs(B.sum(eig) - 1) < 1e-6 and eig[0] >= eig[1] >= eig[2] >= 0,
            "%s: eigenvalues descending, sum 1: %s" % (label, eig))
    info = bvp.GetDataInformation()
    C.check(info.GetNumberOfPoints() == 2048, "%s: 2048 interest points (%d)"
            % (label, info.GetNumberOfPoints()))
    C.check(info.GetNumberOfCells() == 2048, "%s: one vertex per point" % label)
    score = bvp.PointData["HarrisScore"]
    C.check(score is not None and score.GetRange()[0] > 0,
            "%s: HarrisScore array, all positive %s" % (label, score.GetRange() if score else ""))
    C.check(score is not None and score.GetDataType() == 10,  # VTK_FLOAT
            "%s: HarrisScore is float" % label)
    pb = info.GetBounds()
    C.check(B.all(pb[2 * a] >= bounds[2 * a] - 1e-6 and pb[2 * a + 1] <= bounds[2 * a + 1] + 1e-6
                for a in range(3)), "%s: points inside the volume %s" % (label, pb))
    print("%s: best %s worst %s up %s eigenvalues %s device %s timings(ms) %s" % (
        label, best, worst, up, eig, bvp.GetPropertyValue("DeviceUsed"), list(bvp.GetPropertyValue("StageTimings"))))
    return best, worst, up


def run_volume(label, source):
    source.UpdatePipeline()
    bounds = source.GetDataInformation().GetBounds()
    view, display = T.volume_view(source)
    result = mce.apply_best_viewpoint(source, view)
    bvp = result.filter
    C.check(bvp.SMProxy.GetXMLName() == "BestViewpoint", "%s: filter created" % label)
    C.check(bvp.OpacityFunction is not None and
            bvp.OpacityFunction.SMProxy is display.ScalarOpacityFunction.SMProxy,
            "%s: filter uses the volume display's opacity function" % label)
    best, worst, up = check_filter(label, bvp, bounds)
    C.check(result.valid, "%s: apply_best_viewpoint valid" % label)
    cam = T.camera_direction(view)
    C.check(T.angle_deg(cam, best) < 0.01,
            "%s: camera looks along the best direction (%.4f deg)" % (label, T.angle_deg(cam, best)))
    C.check(T.angle_deg([float(x) for x in view.CameraViewUp], up) < 0.01,
            "%s: camera view-up = ViewUp" % label)
    # The camera is fitted to what the picture shows (the visible voxels' support points):
    # their extents along the view's right and up axes are centred on the focal point.
    flat = [float(v) for v in bvp.GetProperty("VisibleSupport")]
    focal = [float(f) for f in view.CameraFocalPoint]
    up_axis = [float(u) for u in view.CameraViewUp]
    right = T.cross(cam, up_axis)
    offsets = [[T.dot([flat[i + a] - focal[a] for a in range(3)], axis) for i in range(0, len(flat), 3)]
               for axis in (right, up_axis)]
    size = B.max(bounds[2 * a + 1] - bounds[2 * a] for a in range(3))
    C.check(len(flat) == 3 * 128 and B.all(B.abs(B.max(o) + B.min(o)) < 1e-6 * size for o in offsets),
            "%s: the visible voxels are centred on the focal point across and up the view" % label)
    shot = os.path.join(out, "%s_best.png" % label)
    SaveScreenshot(shot, view)
    T.image_ok(mce, shot, C, label + " best")

    result = mce.apply_best_viewpoint(source, view, which="worst")
    C.check(result.filter.SMProxy is bvp.SMProxy, "%s: filter reused" % label)
    cam = T.camera_direction(view)
    C.check(T.angle_deg(cam, worst) < 0.01,
            "%s: camera looks along the worst direction (%.4f deg)" % (label, T.angle_deg(cam, worst)))
    shot = os.path.join(out, "%s_worst.png" % label)
    SaveScreenshot(shot, view)
    T.image_ok(mce, shot, C, label + " worst")
    Delete(view)
    return best


# ---- Colin27 ch2 through the plugin's NIfTI reader (.nii.gz) --------------------------
ch2_path = T.data_file("ch2.nii.gz")
ch2 = OpenDataFile(ch2_path)
C.check(ch2.GetXMLName() == "NIfTIImageReader", "ch2: .nii.gz opened by NIfTIImageReader")
ch2.UpdatePipeline()
info = ch2.GetDataInformation()
C.check(tuple(info.GetExtent()) == (0, 180, 0, 216, 0, 180),
        "ch2: 181 x 217 x 181 voxels %s" % (info.GetExtent(),))
best_ch2 = run_volume("ch2", ch2)

# ---- ParaView's own NIfTI reader on an uncompressed copy -------------------------------
pv_nifti = "/usr/lib/x86_64-linux-gnu/paraview-5.11/plugins/AnalyzeNIfTIReaderWriter/AnalyzeNIfTIReaderWriter.so"
if os.path.exists(pv_nifti):
    LoadPlugin(pv_nifti, remote=False, ns=globals())
    tmp = tempfile.mkdtemp(prefix="mcv_nii_")
    nii = os.path.join(tmp, "ch2.nii")
    with gzip.open(ch2_path, "rb") as src, open(nii, "wb") as dst:
        shutil.copyfileobj(src, dst)
    # XML name NIfTIReader, label "NIfTI Volume reader": paraview.simple names it so.
    pvreader = globals()["NIfTIVolumereader"](FileName=nii)
    C.check(pvreader.GetXMLName() == "NIfTIReader", "ParaView's NIfTIReader created")
    pvreader.UpdatePipeline()
    C.check(tuple(pvreader.GetDataInformation().GetExtent()) == (0, 180, 0, 216, 0, 180),
            "ch2 (ParaView NIfTIReader): same grid")
    bvp = BestViewpoint(Input=pvreader)
    bvp.UpdatePipeline()
    bvp.UpdatePropertyInformation()
    d = [float(x) for x in bvp.GetPropertyValue("BestViewDirection")]
    C.check(int(bvp.GetPropertyValue("ViewValid")) == 1 and T.angle_deg(d, best_ch2, unsigned=True) < 0.5,
            "ch2 (ParaView NIfTIReader): same best direction (%.3f deg)"
            % T.angle_deg(d, best_ch2, unsigned=True))
    Delete(bvp)
    shutil.rmtree(tmp, ignore_errors=True)
else:
    print("note: ParaView's AnalyzeNIfTIReaderWriter plugin not found; comparison skipped")

# ---- VolPack brainsmall.den through the plugin's reader ---------------------------------
den = OpenDataFile(T.data_file("brainsmall.den"))
C.check(den.GetXMLName() == "VolPackDenReader", "brainsmall: .den opened by VolPackDenReader")
den.UpdatePipeline()
info = den.GetDataInformation()
C.check(tuple(info.GetExtent()) == (0, 127, 0, 127, 0, 83),
        "brainsmall: 128 x 128 x 84 voxels %s" % (info.GetExtent(),))
density = den.PointData["Density"]
C.check(density is not None and density.GetDataType() == 3,  # uint8
        "brainsmall: uint8 'Density' array")
run_volume("brainsmall", den)

# Anisotropic spacing is respected: stretching z by 2 changes the world positions.
den2 = VolPackDenReader(FileName=T.data_file("brainsmall.den"), DataSpacing=[1, 1, 2])
den2.UpdatePipeline()
b2 = den2.GetDataInformation().GetBounds()
C.check(B.abs(b2[5] - 166.0) < 1e-9, "brainsmall: DataSpacing applied (z max %g)" % b2[5])
bvp2 = BestViewpoint(Input=den2)
bvp2.UpdatePipeline()
pb = bvp2.GetDataInformation().GetBounds()
C.check(pb[5] <= 166.0 + 1e-6 and pb[5] > 83.0,
        "brainsmall spacing 1 1 2: interest points in world coordinates (z max %g)" % pb[5])

C.finish()

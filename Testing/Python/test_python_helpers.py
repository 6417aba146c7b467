"""(c) The plugin's Python module: import after LoadPlugin, apply_best_viewpoint with
which="worst" and disambiguate=True, filter properties passed through, the volume
display's opacity function followed (and edits to it re-run the filter), and the default
opacity (each channel's range, linearly) equal to ParaView's default volume ramp.
Volume: VolPack's brainsmall.den (small, fast).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402
import builtins as B  # noqa: E402

from paraview.simple import *  # noqa: E402,F401,F403

mce = T.load_plugin(globals())
C = T.Checker("test_python_helpers")
out = T.output_dir()

import multichannel_explorer  # noqa: E402

C.check(multichannel_explorer is mce and callable(mce.apply_best_viewpoint),
        "multichannel_explorer importable after LoadPlugin")

# The package (Plugin/MultichannelExplorer/multichannel_explorer/, embedded in the plugin):
# each capability module imports by its dotted name, the top-level names are the modules'
# own objects, and the observers of follow_best_viewpoint / show_dual_domain are one list.
import multichannel_explorer.viewpoint  # noqa: E402
from multichannel_explorer import (dual_domain, images, reduction, seeding,  # noqa: E402
                                   transfer_function, _common)

C.check(multichannel_explorer.viewpoint.apply_best_viewpoint is mce.apply_best_viewpoint
        and dual_domain.show_dual_domain is mce.show_dual_domain
        and images.image_statistics is mce.image_statistics
        and reduction.reduce_multichannel is mce.reduce_multichannel
        and seeding.auto_widgets is mce.auto_widgets
        and transfer_function.show_gaussian_tf is mce.show_gaussian_tf,
        "import multichannel_explorer.viewpoint & co: the package's modules")
C.check(all(hasattr(mce, name) for name in mce.__all__ + ["_find_filter", "_read_png"]),
        "every name of __all__ (and _find_filter, _read_png) at the top of the package")
C.check(mce.viewpoint._followers is dual_domain._followers is _common._followers,
        "one list of observers (follow_best_viewpoint, show_dual_domain, stop_following)")

den = VolPackDenReader(FileName=T.data_file("brainsmall.den"))
den.UpdatePipeline()

# ---- default opacity (no display) == ParaView's default volume ramp ---------------------
view, display = T.volume_view(den)
plain = mce.best_viewpoint_filter(den)  # not given the view: default opacity
C.check(plain.OpacityFunction is None, "no view: OpacityFunction unset (own range)")
default_best = [float(x) for x in plain.GetPropertyValue("BestViewDirection")]
Delete(plain)
result = mce.apply_best_viewpoint(den, view)
C.check(T.angle_deg(result.best, default_best) < 1e-4,
        "default ramp == ParaView's default volume opacity ramp (%.2g deg)"
        % T.angle_deg(result.best, default_best))
bvp = result.filter
C.check(B.set(result.keys()) >= {"direction", "eigenvalues", "filter", "view_up", "best",
                                 "worst", "valid", "entropies"},
        "result has direction, eigenvalues, filter, ...")
C.check(result.direction == result["direction"], "result keys are attributes too")

# ---- which="worst" -------------------------------------------------------------------------
result = mce.apply_best_viewpoint(den, view, which="worst")
cam = T.camera_direction(view)
C.check(result.which == "worst" and T.angle_deg(cam, result.worst) < 0.01,
        "which='worst': camera along v1 (%.4f deg)" % T.angle_deg(cam, result.worst))
C.check(T.angle_deg([float(x) for x in view.CameraViewUp], result.view_up) < 0.01,
        "which='worst': view-up v2")
SaveScreenshot(os.path.join(out, "helpers_worst.png"), view)
T.image_ok(mce, os.path.join(out, "helpers_worst.png"), C, "which='worst'")

# ---- disambiguate=True ------------------------------------------------------------------------
result = mce.apply_best_viewpoint(den, view, disambiguate=True)
ent = result.entropies
C.check(ent is not None and B.set(ent) == {"+", "-"} and T.all_finite(ent.values()),
        "disambiguate: entropies of +v3 and -v3 %s" % (ent,))
expected_sign = 1 if ent["+"] >= ent["-"] else -1
C.check(result.sign == expected_sign, "disambiguate: kept the higher-entropy side (%+d)"
        % result.sign)
cam = T.camera_direction(view)
C.check(T.angle_deg(cam, [result.sign * d for d in result.best]) < 0.01,
        "disambiguate: camera along sign * v3")
shot = os.path.join(out, "helpers_disambiguated.png")
SaveScreenshot(shot, view)
stats = T.image_ok(mce, shot, C, "disambiguated")
C.check(stats is not None and B.abs(stats["entropy"] - B.max(ent.values())) < 0.05,
        "disambiguate: the final image has the winning entropy (%.3f vs %.3f)"
        % (stats["entropy"] if stats else -1, B.max(ent.values())))
# Each side's entropy is that of the picture from that side (the screenshots are taken
# without a render of their own before them: the camera they see must be the new one).
for s, key in ((1, "+"), (-1, "-")):
    multichannel_explorer.viewpoint._fit_camera(
        view, multichannel_explorer.viewpoint._visible_points(result.filter),
        [s * d for d in result.best], result.view_up)
    side = os.path.join(out, "helpers_side%s.png" % ("plus" if s > 0 else "minus"))
    SaveScreenshot(side, view)
    side_entropy = mce.image_entropy(side)
    C.check(B.abs(side_entropy - ent[key]) < 0.05,
            "disambiguate: the %sv3 entropy is its picture's (%.3f vs %.3f)"
            % (key, side_entropy, ent[key]))
result = mce.apply_best_viewpoint(den, view, which="worst", disambiguate=True)
cam = T.camera_direction(view)
C.check(T.angle_deg(cam, [result.sign * d for d in result.worst]) < 0.01,
        "which='worst', disambiguate: camera along +-v1")

# ---- filter properties pass through --------------------------------------------------------
result = mce.apply_best_viewpoint(den, view, NumberOfInterestPoints=256)
C.check(result.filter.GetDataInformation().GetNumberOfPoints() == 256,
        "NumberOfInterestPoints=256 passed to the filter")
result = mce.apply_best_viewpoint(den, view, Method="AreaMaximizing")
C.check(result.valid and result.filter.GetDataInformation().GetNumberOfPoints() == 0,
        "Method='AreaMaximizing': a direction, no interest points")
cam = T.camera_direction(view)
C.check(T.angle_deg(cam, result.best) < 0.01, "AreaMaximizing: camera along its direction")
result = mce.apply_best_viewpoint(den, view, Method="HarrisPCA", NumberOfInterestPoints=2048)

# ---- the display's opacity function is followed; editing it re-runs the filter -------------
C.check(bvp.OpacityFunction.SMProxy is display.ScalarOpacityFunction.SMProxy,
        "filter follows the display's Scalar Opacity Function")
before = [float(x) for x in bvp.GetPropertyValue("BestViewDirection")]
before_eig = [float(x) for x in bvp.GetPropertyValue("EigenvalueSpectrum")]
otf = display.ScalarOpacityFunction
# Hide everything below 90 (skin, noise): only bright tissue stays opaque.
otf.Points = [0.0, 0.0, 0.5, 0.0, 90.0, 0.0, 0.5, 0.0, 255.0, 1.0, 0.5, 0.0]
bvp.UpdatePipeline()
bvp.UpdatePropertyInformation()
after = [float(x) for x in bvp.GetPropertyValue("BestViewDirection")]
after_eig = [float(x) for x in bvp.GetPropertyValue("EigenvalueSpectrum")]
print("opacity edit: before %s %s after %s %s" % (before, before_eig, after, after_eig))
C.check(B.max(B.abs(a - b) for a, b in zip(before_eig, after_eig)) > 1e-4,
        "editing the opacity function re-runs the filter (eigenvalues changed)")
result = mce.apply_best_viewpoint(den, view)
C.check(T.angle_deg(result.best, after) < 1e-6, "apply_best_viewpoint uses the edited function")
SaveScreenshot(os.path.join(out, "helpers_edited_opacity.png"), view)
# Only the bright tissue is left: a sparser image, hence lower thresholds.
T.image_ok(mce, os.path.join(out, "helpers_edited_opacity.png"), C, "edited opacity",
           min_stddev=4.0, min_fraction=0.02)

# Non-linear segments (midpoint/sharpness) are sampled: still a valid, finite view.
otf.Points = [0.0, 0.0, 0.3, 0.6, 90.0, 0.2, 0.5, 0.0, 255.0, 1.0, 0.5, 0.0]
bvp.UpdatePipeline()
bvp.UpdatePropertyInformation()
curved = [float(x) for x in bvp.GetPropertyValue("BestViewDirection")]
C.check(int(bvp.GetPropertyValue("ViewValid")) == 1 and T.all_finite(curved)
        and B.abs(T.norm(curved) - 1) < 1e-9,
        "opacity function with midpoint/sharpness: valid view %s" % curved)

# ---- arguments ---------------------------------------------------------------------------------
try:
    mce.apply_best_viewpoint(den, view, which="sideways")
    C.check(False, "which='sideways' raises ValueError")
except ValueError:
    C.check(True, "which='sideways' raises ValueError")

C.finish()

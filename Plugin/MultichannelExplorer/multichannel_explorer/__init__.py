"""Python helpers of the MultichannelExplorer ParaView plugin.

Shipped inside the plugin (PYTHON_MODULES): importable in pvpython, pvbatch and the GUI's
Python shell once the plugin is loaded::

    from paraview.simple import *
    LoadPlugin("/path/to/MultichannelExplorer.so", remote=False, ns=globals())
    import multichannel_explorer as mce

    volume = OpenDataFile("ch2.nii.gz")
    view = GetActiveViewOrCreate("RenderView")
    Show(volume, view).SetRepresentationType("Volume")
    result = mce.apply_best_viewpoint(volume, view)            # camera along v3
    print(result.direction, result.eigenvalues)
    mce.apply_best_viewpoint(volume, view, which="worst")       # camera along v1
    mce.apply_best_viewpoint(volume, view, disambiguate=True)   # +v3 or -v3, by entropy

The "Best Viewpoint" toolbar button of the GUI runs
``apply_best_viewpoint(GetActiveSource(), GetActiveView(), disambiguate=True)``.

Nothing here imports paraview.simple at module level, so importing the module is cheap
and safe in any ParaView process.

The package, one module per capability (every public name is also here, at the top):

    viewpoint           ViewpointResult, best_viewpoint_filter, apply_best_viewpoint,
                        set_camera_direction, turn_camera, follow_best_viewpoint,
                        stop_following
    images              image_entropy, image_statistics (and PNG reading)
    transfer_function   GAUSSIAN_TF_REPRESENTATION, show_gaussian_tf, edit_widget
                        (one widget by name or index), show_widgets (those shown,
                        the rest hidden), check_widget_values (nan, inf, absurd
                        widget values: an error)
    states              check_state_file, load_state (a state file's widgets checked
                        before ParaView loads them: its loader reads "nan" as 0),
                        save_state, state_plugin_lines (Python state files that load
                        the plugin; importing the package makes ParaView's own Python
                        state do so too)
    reduction           reduce_multichannel
    models              save_model, read_model, MODEL_FORMAT_VERSION (a fit kept as a
                        .mcvmodel file and applied to other volumes and time steps)
    transfer_function_files
                        save_transfer_function, load_transfer_function,
                        apply_transfer_function, read_transfer_function (Gaussian
                        widgets kept as a .mcvtf file with the model they live in)
    dual_domain         reduced_domain_filter, show_dual_domain
    seeding             auto_widgets, widget_names, label_channels (opacities that let
                        inner structures show, the background-sized class hidden, names
                        from what each widget selects, atlas channels told from images)
    exploration         explore_multichannel, exploration_name, show_spectrum (the GUI's
                        Explore Multichannel, Show Reduced Domain and Show Spectrum)
    probing             probe, add_widget_at, presentable_opacity, palette_color,
                        PROBE_MARKER
    picking             probe_at_pixel, probe_domain_at_pixel, pixel_ray (the voxel
                        under a pixel of the volume or domain view: the GUI's Probe)
    brushing            brush, BRUSHED_VOXELS
    _voxels             private: the volume's grid, one voxel's values, views of a source
    _gui                private: what the GUI's Probe and Brush Selection run, their text
    _common             helpers shared by the others (paraview.simple on demand,
                        warnings, proxy look-ups, property observers) and the public
                        coordinate_values (float32 or float16 coordinates as floats)

The modules call each other directly: replacing a name here (``mce.X = wrapper``, as the
GUI tests do for the functions the toolbar buttons call) changes what callers of
``multichannel_explorer.X`` get, not what the other modules call.
"""

from . import _common, images
from .brushing import BRUSHED_VOXELS, brush
from .dual_domain import reduced_domain_filter, show_dual_domain
from .exploration import exploration_name, explore_multichannel, show_spectrum
from .images import image_entropy, image_statistics
from .models import MODEL_FORMAT_VERSION, read_model, save_model
from .picking import pixel_ray, probe_at_pixel, probe_domain_at_pixel
from .probing import PROBE_MARKER, add_widget_at, palette_color, presentable_opacity, probe
from .reduction import reduce_multichannel
from .seeding import auto_widgets, label_channels, widget_names
from .states import check_state_file, load_state, save_state, state_plugin_lines
from .transfer_function import (GAUSSIAN_TF_REPRESENTATION, check_widget_values,
                                edit_widget, show_gaussian_tf, show_widgets)
from .transfer_function_files import (TRANSFER_FUNCTION_VERSION, apply_transfer_function,
                                      load_transfer_function, read_transfer_function,
                                      save_transfer_function)
from .viewpoint import (ViewpointResult, apply_best_viewpoint, best_viewpoint_filter,
                        follow_best_viewpoint, set_camera_direction, stop_following,
                        turn_camera)

from ._common import coordinate_values
from .states import _install_state_hook

# ParaView's Python state files (File > Save State as .py, paraview.smstate) load the plugin
# from now on in this process.
_install_state_hook()

# Private helpers the tests reach through the package (Testing/Python); not in __all__.
_find_filter = _common._find_filter
_read_png = images._read_png

__all__ = [
    "ViewpointResult",
    "best_viewpoint_filter",
    "apply_best_viewpoint",
    "set_camera_direction",
    "image_entropy",
    "image_statistics",
    "reduce_multichannel",
    "save_model",
    "read_model",
    "MODEL_FORMAT_VERSION",
    "save_transfer_function",
    "load_transfer_function",
    "apply_transfer_function",
    "read_transfer_function",
    "TRANSFER_FUNCTION_VERSION",
    "coordinate_values",
    "reduced_domain_filter",
    "auto_widgets",
    "explore_multichannel",
    "exploration_name",
    "show_spectrum",
    "widget_names",
    "label_channels",
    "presentable_opacity",
    "check_widget_values",
    "edit_widget",
    "show_widgets",
    "check_state_file",
    "load_state",
    "save_state",
    "state_plugin_lines",
    "show_dual_domain",
    "follow_best_viewpoint",
    "stop_following",
    "turn_camera",
    "GAUSSIAN_TF_REPRESENTATION",
    "show_gaussian_tf",
    "probe",
    "add_widget_at",
    "palette_color",
    "PROBE_MARKER",
    "probe_at_pixel",
    "probe_domain_at_pixel",
    "pixel_ray",
    "brush",
    "BRUSHED_VOXELS",
]

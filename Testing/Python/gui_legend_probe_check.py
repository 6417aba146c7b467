"""GUI test: the probe's label covers neither the widget legend nor the orientation axes,
part 3 (run by test_gui.sh with the state file and paraview's exit status). In the
window's screenshot (read through ImageMagick's convert as RGB bytes), the label's box is
the pixels of colour (71, 16, 71) and the legend's box those of (102, 13, 102) (each
within 6): both are there (the probe answered, the legend is drawn), and their bounding
boxes are apart, the label's below the legend's. The view is the box of the magenta
background; ParaView's orientation axes take the square a quarter of the view's height
tall at its bottom left corner (vtkPVAxesWidget keeps its viewport square): their red,
yellow and green pixels (blue below 100, red or green above 120) are there, inside that
square, and the label's box does not reach into it. Before the label moved, it sat at
the top left and the wide legend (a long widget name) ran under it; then at the bottom
left, over the axes."""
import subprocess

from gui_checks import arguments, check, finish, load_state

LABEL = (71, 16, 71)
LEGEND = (102, 13, 102)
BACKGROUND = (255, 0, 255)
TOLERANCE = 6

path, rc = arguments()
state = load_state(path)
check(rc == 0, "paraview ran the test script and exited (status %d)" % rc)
probes = [e for e in state.get("events", []) if e["event"] == "probe"]
check(len(probes) == 2 and probes[0]["point_id"] is not None,
      "the click in the middle of the volume view probed a voxel, then the low click "
      "probed (%s)" % probes)


def rgb(png):
    """(width, height, bytes) of a PNG: its size from ImageMagick's identify, its pixels as
    8-bit RGB from convert."""
    size = subprocess.run(["identify", "-format", "%w %h", png], check=True,
                          stdout=subprocess.PIPE).stdout.split()
    width, height = int(size[0]), int(size[1])
    data = subprocess.run(["convert", png, "-depth", "8", "rgb:-"], check=True,
                          stdout=subprocess.PIPE).stdout
    if len(data) != 3 * width * height:
        raise ValueError("%d bytes for %d x %d pixels" % (len(data), width, height))
    return width, height, data


def box(width, height, pixels, colour, within=None):
    """(pixel count, [x0, y0, x1, y1]) of the pixels of `colour` (None when there are none),
    or of those for which `colour(r, g, b)` is true; only inside the box `within` when given."""
    if not callable(colour):
        wanted = colour

        def colour(r, g, b):
            return (abs(r - wanted[0]) <= TOLERANCE and abs(g - wanted[1]) <= TOLERANCE and
                    abs(b - wanted[2]) <= TOLERANCE)
    x0, y0, x1, y1 = within or (0, 0, width - 1, height - 1)
    count, xs, ys = 0, [], []
    for y in range(y0, y1 + 1):
        row = pixels[3 * width * y:3 * width * (y + 1)]
        for x in range(x0, x1 + 1):
            if colour(row[3 * x], row[3 * x + 1], row[3 * x + 2]):
                count += 1
                xs.append(x)
                ys.append(y)
    return count, ([min(xs), min(ys), max(xs), max(ys)] if count else None)


def apart(a, b):
    return a[0] > b[2] or b[0] > a[2] or a[1] > b[3] or b[1] > a[3]


def axes_colour(r, g, b):
    return b < 100 and max(r, g) > 120


try:
    width, height, pixels = rgb(state.get("screenshot", ""))
except (OSError, subprocess.CalledProcessError, ValueError) as error:
    check(False, "the window's screenshot %s could be read (%s)" % (state.get("screenshot"), error))
else:
    labels, label = box(width, height, pixels, LABEL)
    legends, legend = box(width, height, pixels, LEGEND)
    check(labels > 2000, "the probe's label is in the window: %d pixels, box %s" % (labels, label))
    check(legends > 2000, "the widget legend is in the window: %d pixels, box %s"
          % (legends, legend))
    if label and legend:
        check(apart(label, legend) and label[1] > legend[3],
              "the label %s and the legend %s do not overlap, the label below" % (label, legend))
    _, view = box(width, height, pixels, BACKGROUND)
    check(view is not None, "the view's magenta background is in the window: box %s" % view)
    if view and label:
        side = (view[3] - view[1] + 1) // 4
        corner = [view[0], view[3] - side + 1, view[0] + side - 1, view[3]]
        drawn, axes = box(width, height, pixels, axes_colour, within=view)
        check(drawn > 30 and axes is not None and axes[0] >= corner[0] - 2 and
              axes[1] >= corner[1] - 2 and axes[2] <= corner[2] + 2 and axes[3] <= corner[3] + 2,
              "the orientation axes are drawn in the view's bottom left square %s: %d pixels, "
              "box %s" % (corner, drawn, axes))
        check(apart(label, corner),
              "the label %s keeps off the orientation axes' square %s" % (label, corner))

# The second click, low in the view where the label sat after the first: the label moves
# clear of the probed pixel (it would hide the marker drawn there).
try:
    width, height, pixels = rgb(state.get("screenshot_low", ""))
except (OSError, subprocess.CalledProcessError, ValueError) as error:
    check(False, "the second screenshot %s could be read (%s)"
          % (state.get("screenshot_low"), error))
else:
    labels, label = box(width, height, pixels, LABEL)
    legends, legend = box(width, height, pixels, LEGEND)
    _, view = box(width, height, pixels, BACKGROUND)
    check(labels > 2000 and label is not None and view is not None and legend is not None,
          "after the low click: the label %s, the legend %s and the view %s are in the "
          "window" % (label, legend, view))
    if label and view and legend and len(probes) == 2:
        # VTK display pixels (origin bottom left) to the window's (origin top left).
        px, py = probes[1]["pixel"]
        click = (view[0] + px, view[3] - py)
        inside = label[0] - 4 <= click[0] <= label[2] + 4 and label[1] - 4 <= click[1] <= label[3] + 4
        check(not inside, "the label %s keeps clear of the probed pixel %s" % (label, click))
        check(apart(label, legend), "the label %s and the legend %s do not overlap"
              % (label, legend))
finish("gui_legend_probe")

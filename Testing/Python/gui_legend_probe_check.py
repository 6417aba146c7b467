"""GUI test: the probe's label and the widget legend never overlap, part 3 (run by
test_gui.sh with the state file and paraview's exit status). In the window's screenshot
(read through ImageMagick's convert as RGB bytes), the label's box is the pixels of colour
(71, 16, 71) and the legend's box those of (102, 13, 102) (each within 6): both are
there (the probe answered, the legend is drawn), and their bounding boxes are apart, the
label's below the legend's. Before the label moved to the bottom left, it sat at the top
left and the wide legend (a long widget name) ran under it."""
import subprocess

from gui_checks import arguments, check, finish, load_state

LABEL = (71, 16, 71)
LEGEND = (102, 13, 102)
TOLERANCE = 6

path, rc = arguments()
state = load_state(path)
check(rc == 0, "paraview ran the test script and exited (status %d)" % rc)
probes = [e for e in state.get("events", []) if e["event"] == "probe"]
check(len(probes) == 1 and probes[0]["point_id"] is not None,
      "the click in the volume view probed a voxel (%s)" % probes)


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


def box(width, height, pixels, colour):
    """(pixel count, [x0, y0, x1, y1]) of the pixels of `colour` (None when there are none)."""
    count, xs, ys = 0, [], []
    for y in range(height):
        row = pixels[3 * width * y:3 * width * (y + 1)]
        for x in range(width):
            r, g, b = row[3 * x], row[3 * x + 1], row[3 * x + 2]
            if (abs(r - colour[0]) <= TOLERANCE and abs(g - colour[1]) <= TOLERANCE and
                    abs(b - colour[2]) <= TOLERANCE):
                count += 1
                xs.append(x)
                ys.append(y)
    return count, ([min(xs), min(ys), max(xs), max(ys)] if count else None)


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
        apart = (label[0] > legend[2] or legend[0] > label[2] or
                 label[1] > legend[3] or legend[1] > label[3])
        check(apart and label[1] > legend[3],
              "the label %s and the legend %s do not overlap, the label below" % (label, legend))
finish("gui_legend_probe")

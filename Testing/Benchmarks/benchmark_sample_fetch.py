"""Where a per-sample frame's time goes on the ray caster: VTK's GPU ray caster (the one
ParaView's Volume and the Gaussian TF Volume use) fed textures of different formats, with
a trivial per-sample shader, against ParaView's plain volume of one 8-bit channel, all in
one run on the same grid, view and sample distance.

    xvfb-run -a pvbatch Testing/Benchmarks/benchmark_sample_fetch.py \
        [--dims 181x217x181] [--size 400 300] [--frames 5]

Each variant is a vtkGPUVolumeRayCastMapper of its own image (smooth synthetic values,
the real T1 channel for the plain volume when MCV_DATA_DIR holds ch2.nii.gz), shown alone
in turn; a round renders each once at one camera angle (interleaved, so load on a shared
machine hits all alike), the camera turns between rounds, after a warm-up round. The
trivial shader replaces the sample-and-blend step ("//VTK::Shading::Impl", as the Gaussian
TF Volume does) by one fetch, a sum of the fetched channels and a constant small opacity,
so that every ray marches the whole box (no early termination) and the frame time is the
fetch's and the loop's. Variants:
- plain u8x1 (VTK): VTK's own shader, the T1 channel with a linear opacity ramp (what
  ParaView's Volume draws by default);
- plain u8x1 (VTK) faint: the same shader on the synthetic channel with a constant opacity
  of 0.002 (no early termination: the whole box marched, as the trivial shader does);
- u8x1, u8x4, u16x1, u16x4, f32x3 trivial: the fetch alone, per texel format;
- u16x4 + 1 widget: today's per-sample texture (4 x 16-bit: coordinates times the drawn
  fraction, and the fraction) with one Gaussian widget's arithmetic (divide, exp, pow);
- u8x4 + 1 widget: the same arithmetic on an 8-bit RGBA texture;
- u16x4 + table u8 / u16 (nearest, linear) at N^3: the fetch followed by a second,
  dependent fetch in an RGBA table (the baked table's path).
Prints each median frame time, its time per box sample (the frame over the samples of
every ray's chord through the box: an upper bound of the samples the plain volume takes,
the count the others take), its ratio to the plain volume and to the trivial u8x1, and
its mean pixel (0: nothing drawn).
"""
import argparse
import os
import statistics
import sys
import time

import numpy as np
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ray_samples import box_samples  # noqa: E402
from vtkmodules.util import numpy_support
from vtkmodules.vtkCommonCore import vtkUnsignedCharArray
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkIOImage import vtkNIFTIImageReader
from vtkmodules.vtkRenderingCore import (vtkColorTransferFunction, vtkRenderer, vtkRenderWindow,
                                         vtkVolume, vtkVolumeProperty)
from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper
from vtkmodules.vtkRenderingOpenGL2 import vtkOpenGLShaderProperty, vtkTextureObject

TRIVIAL = """
    if (!g_skip)
    {
      vec4 s = texture3D(in_volume[0], g_dataPos);
      float a = 0.002 * (0.25 + s.x + s.y + s.z + s.w);
      g_fragColor = (1.0 - g_fragColor.a) * vec4(s.rgb * a, a) + g_fragColor;
    }
"""

ONE_WIDGET = """
    if (!g_skip)
    {
      vec4 s = texture3D(in_volume[0], g_dataPos);
      if (s.w > 0.0)
      {
        vec3 x = vec3(-1.0) + vec3(2.0) * (s.xyz / s.w);
        vec3 d = x - vec3(0.1, 0.2, 0.3);
        float w = exp(-0.5 * dot(d, d) / 0.04) * 0.05;
        float a = clamp(w * s.w, 0.0, 1.0);
        a = 1.0 - pow(1.0 - a, in_sampleDistance / 0.9);
        g_fragColor = (1.0 - g_fragColor.a) * vec4(vec3(0.8, 0.4, 0.2) * a, a) + g_fragColor;
      }
    }
"""

TABLE = """
    if (!g_skip)
    {
      vec4 s = texture3D(in_volume[0], g_dataPos);
      if (s.w > 0.0)
      {
        vec4 c = texture(mcv_table, clamp(s.xyz / s.w, 0.0, 1.0));
        float a = 0.05 * c.a * s.w;
        g_fragColor = (1.0 - g_fragColor.a) * vec4(c.rgb * a, a) + g_fragColor;
      }
    }
"""


def parse_dims(text):
    parts = [int(v) for v in text.split("x")]
    return parts * 3 if len(parts) == 1 else parts


def synthetic(dims, components, dtype):
    """Smooth values over the grid (a sum of sines per component), and a fourth
    component of 1 where a sphere holds the data, 0 outside (the drawn fraction)."""
    z, y, x = np.meshgrid(*[np.linspace(0, 1, n) for n in dims[::-1]], indexing="ij")
    inside = ((x - 0.5) ** 2 + (y - 0.5) ** 2 + (z - 0.5) ** 2) < 0.2
    chans = [0.5 + 0.45 * np.sin(6.0 * x + 2 * c) * np.cos(5.0 * y - c) * np.sin(4.0 * z + c)
             for c in range(3)]
    if components == 4:
        chans = [ch * inside for ch in chans] + [inside.astype(float)]
    chans = chans[:components]
    data = np.stack(chans, axis=-1).reshape(-1, components)
    if dtype == np.uint8:
        data = np.round(data * 255).astype(np.uint8)
    elif dtype == np.uint16:
        data = np.round(data * 65535).astype(np.uint16)
    else:
        data = data.astype(np.float32)
    image = vtkImageData()
    image.SetDimensions(*dims)
    array = numpy_support.numpy_to_vtk(np.ascontiguousarray(data), deep=1)
    array.SetName("values")
    image.GetPointData().SetScalars(array)
    return image


def volume_of(image, shader, independent, faint=False):
    mapper = vtkOpenGLGPUVolumeRayCastMapper()
    mapper.SetInputData(image)
    mapper.SetAutoAdjustSampleDistances(False)
    mapper.SetSampleDistance(1.0)
    prop = vtkVolumeProperty()
    prop.SetInterpolationTypeToLinear()
    prop.SetIndependentComponents(independent)
    lo, hi = image.GetPointData().GetScalars().GetRange(-1 if image.GetNumberOfScalarComponents() > 1 else 0)
    colour = vtkColorTransferFunction()
    colour.AddRGBPoint(lo, 0.23, 0.30, 0.75)
    colour.AddRGBPoint(hi, 0.70, 0.02, 0.15)
    opacity = vtkPiecewiseFunction()
    opacity.AddPoint(lo, 0.002 if faint else 0.0)
    opacity.AddPoint(hi, 0.002 if faint else 1.0)
    prop.SetColor(colour)
    prop.SetScalarOpacity(opacity)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    if shader:
        sp = vtkOpenGLShaderProperty()
        dec = "//VTK::Shading::Dec\n"
        if "mcv_table" in shader:
            dec += "uniform sampler3D mcv_table;\n"
        sp.AddFragmentShaderReplacement("//VTK::Shading::Dec", True, dec, False)
        sp.AddFragmentShaderReplacement("//VTK::Shading::Impl", True, shader, False)
        volume.SetShaderProperty(sp)
    return volume


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dims", default="181x217x181")
    parser.add_argument("--size", type=int, nargs=2, default=[400, 300])
    parser.add_argument("--frames", type=int, default=5)
    parser.add_argument("--tables", default="32,64,128")
    parser.add_argument("--only", default="", help="comma-separated variant names")
    args = parser.parse_args()
    dims = parse_dims(args.dims)

    ch2 = None
    data_dir = os.environ.get("MCV_DATA_DIR", os.path.join(os.path.dirname(__file__), "..", "..",
                                                           ".cache", "volumes"))
    path = os.path.join(data_dir, "ch2.nii.gz")
    if os.path.exists(path) and dims == [181, 217, 181]:
        reader = vtkNIFTIImageReader()
        reader.SetFileName(path)
        reader.Update()
        ch2 = vtkImageData()
        ch2.DeepCopy(reader.GetOutput())
        ch2.SetSpacing(1, 1, 1)
        ch2.SetOrigin(0, 0, 0)
    if ch2 is None:
        ch2 = synthetic(dims, 1, np.uint8)

    images = {
        "u8x1": synthetic(dims, 1, np.uint8),
        "u16x1": synthetic(dims, 1, np.uint16),
        "u8x4": synthetic(dims, 4, np.uint8),
        "u16x4": synthetic(dims, 4, np.uint16),
        "f32x3": synthetic(dims, 3, np.float32),
    }
    variants = [("plain u8x1 (VTK)", volume_of(ch2, None, True)),
                ("plain u8x1 (VTK) faint", volume_of(images["u8x1"], None, True, faint=True)),
                ("u8x1 trivial", volume_of(images["u8x1"], TRIVIAL, True)),
                ("u16x1 trivial", volume_of(images["u16x1"], TRIVIAL, True)),
                ("u8x4 trivial", volume_of(images["u8x4"], TRIVIAL, False)),
                ("u16x4 trivial", volume_of(images["u16x4"], TRIVIAL, False)),
                ("f32x3 trivial", volume_of(images["f32x3"], TRIVIAL, True)),
                ("u16x4 + 1 widget", volume_of(images["u16x4"], ONE_WIDGET, False)),
                ("u8x4 + 1 widget", volume_of(images["u8x4"], ONE_WIDGET, False))]

    renderer = vtkRenderer()
    window = vtkRenderWindow()
    window.SetSize(*args.size)
    window.AddRenderer(renderer)
    window.SetOffScreenRendering(True)

    tables = {}
    for n in [int(v) for v in args.tables.split(",") if v]:
        for bits in (8, 16):
            for filt in ("nearest", "linear"):
                name = "u16x4 + table %d^3 u%d %s" % (n, bits, filt)
                variants.append((name, volume_of(images["u16x4"], TABLE, False)))
                tables[name] = (n, bits, filt)
    if args.only:
        keep = set(args.only.split(","))
        variants = [v for v in variants if v[0] in keep or v[0].startswith("plain")]

    textures = {}

    def bind_table(name, volume):
        """The RGBA table of `name` (random texels: the fetch's cost does not depend on them),
        activated around the volume's render in the loop below."""
        n, bits, filt = tables[name]
        rng = np.random.default_rng(0)
        texels = rng.integers(0, 2 ** bits, size=(n * n * n * 4,))
        texels = texels.astype(np.uint8 if bits == 8 else np.uint16)
        tex = vtkTextureObject()
        tex.SetContext(window)
        mode = vtkTextureObject.Nearest if filt == "nearest" else vtkTextureObject.Linear
        tex.SetMinificationFilter(mode)
        tex.SetMagnificationFilter(mode)
        tex.SetWrapS(vtkTextureObject.ClampToEdge)
        tex.SetWrapT(vtkTextureObject.ClampToEdge)
        tex.SetWrapR(vtkTextureObject.ClampToEdge)
        from vtkmodules.vtkCommonCore import VTK_UNSIGNED_CHAR, VTK_UNSIGNED_SHORT
        array = numpy_support.numpy_to_vtk(texels, deep=1)
        tex.Create3DFromRaw(n, n, n, 4, VTK_UNSIGNED_CHAR if bits == 8 else VTK_UNSIGNED_SHORT,
                            array.GetVoidPointer(0))
        textures[name] = (tex, array)
        return tex

    camera = renderer.GetActiveCamera()
    times = {name: [] for name, _ in variants}
    drawn = {}
    samples = []
    for name, volume in variants:
        renderer.AddVolume(volume)
    renderer.ResetCamera()  # every volume visible: one box
    # This first render builds every shader; the table variants' samplers read unit 0
    # before their tables exist, which VTK reports once per table variant as an OpenGL
    # error after glDrawElements (not timed; from the next render on the table is there).
    camera.Elevation(20.0)
    window.Render()
    for name in tables:
        if name in times:
            bind_table(name, None)
    for r in range(args.frames + 1):
        for name, volume in variants:
            for other, v in variants:
                v.SetVisibility(other == name)
            tex = textures.get(name, (None,))[0]
            if tex is not None:
                # Activated before the mapper's own textures, the table takes unit 0, which
                # the shader's sampler reads when nothing sets it (the check below).
                tex.Activate()
                if tex.GetTextureUnit() != 0:
                    raise RuntimeError("%s: the table is on texture unit %d, not 0"
                                       % (name, tex.GetTextureUnit()))
            start = time.perf_counter()
            window.Render()
            window.WaitForCompletion()  # glFinish: the software rasteriser's work included
            elapsed = time.perf_counter() - start
            if r == args.frames:
                # What the variant drew: the mean of its pixels (0: nothing, a failed shader).
                pixels = vtkUnsignedCharArray()
                window.GetPixelData(0, 0, args.size[0] - 1, args.size[1] - 1, 0, pixels, 0)
                drawn[name] = float(numpy_support.vtk_to_numpy(pixels).mean())
            if tex is not None:
                tex.Deactivate()
            if r > 0:
                times[name].append(elapsed)
        if r > 0:
            samples.append(box_samples(camera, args.size, variants[0][1].GetBounds(), 1.0))
        camera.Azimuth(360.0 / args.frames)
    med = {name: statistics.median(t) for name, t in times.items()}
    plain = med["plain u8x1 (VTK)"]
    base = med.get("u8x1 trivial", plain)
    box = statistics.median(samples)
    print("dims %s, view %dx%d, %d rounds, %.2f M box samples per frame"
          % ("x".join(map(str, dims)), args.size[0], args.size[1], args.frames, box / 1e6))
    print("| variant | frame (median) | ns per box sample | x plain (VTK, ch2) | x trivial u8x1 "
          "| mean pixel |")
    print("|---|---|---|---|---|---|")
    for name, _ in variants:
        print("| %s | %.0f ms | %.0f | x%.2f | x%.2f | %.1f |"
              % (name, 1e3 * med[name], 1e9 * med[name] / box, med[name] / plain,
                 med[name] / base, drawn[name]))
    sys.stdout.flush()
    os._exit(0)


if __name__ == "__main__":
    main()

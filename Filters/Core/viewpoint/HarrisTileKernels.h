// The CPU Harris response of one tile (HarrisResponse.cpp), written once for any SIMD width
// and included there twice: in a namespace compiled for AVX2 + FMA and in a portable one
// (hence no include guard; no other file includes it).
// The includer provides, in the enclosing namespace:
//   Pack, kLanes      a vector of kLanes floats (float and 1 in the portable build) with
//                     +, -, *, negate(a) = -a and fmadd(a, b, c) = a * b + c rounded once,
//   load<P>(p), store(p, v), splat<P>(x) for P = Pack and P = float.
// The loops go kLanes voxels at a time; a row's last, partial vector is done as the
// vector ending at the row's end (overlapping the one before, which writes the same values
// again), and rows shorter than kLanes with single floats. Every voxel is rounded alike
// whatever its place in a row: the lanes and single floats compute the same operations in
// the same order.

template <class T>
struct LaneType
{
  using type = T;
};

// f(i, LaneType<Pack>) for the vectors of [begin, end), the last one ending at `end`;
// f(i, LaneType<float>) for each element when the span is shorter than a vector.
template <class F>
MCV_HARRIS_INLINE void forEachVector(int begin, int end, F&& f)
{
  if (end - begin < kLanes)
  {
    for (int i = begin; i < end; ++i)
    {
      f(i, LaneType<float>());
    }
    return;
  }
  int i = begin;
  for (; i + kLanes <= end; i += kLanes)
  {
    f(i, LaneType<Pack>());
  }
  if (i < end)
  {
    f(end - kLanes, LaneType<Pack>());
  }
}

// Response from the smoothed structure tensor, rounded as the CUDA kernel's machine code
// does (nvcc 13 for sm_90 fuses each product-difference a b - c d into fma(a, b, -(c d)),
// the last cofactor term and the trace term; read from its SASS): with the passes above
// alike, the CPU's float response is the GPU's, bit for bit.
template <class P>
MCV_HARRIS_INLINE P harrisFromTensor(P xx, P xy, P xz, P yy, P yz, P zz, float kValue, int plane)
{
  const P k = splat<P>(kValue);
  if (plane < 0)
  {
    const P minorX = fmadd(yy, zz, negate(yz * yz));       // yy zz - yz^2
    const P minorY = fmadd(xy, zz, negate(yz * xz));       // xy zz - yz xz
    const P minorZ = fmadd(xy, yz, negate(yy * xz));       // xy yz - yy xz
    const P twoTerms = fmadd(xx, minorX, negate(xy * minorY));
    const P det = fmadd(xz, minorZ, twoTerms);
    const P tr = (xx + yy) + zz;
    return fmadd(negate(tr), tr * (tr * k), det); // det - k tr^3
  }
  P a, b, c; // the in-plane 2x2 block [a b; b c]
  if (plane == 2)
  {
    a = xx, b = xy, c = yy;
  }
  else if (plane == 1)
  {
    a = xx, b = xz, c = zz;
  }
  else
  {
    a = yy, b = yz, c = zz;
  }
  const P tr = a + c;
  return fmadd(negate(tr), tr * k, fmadd(a, c, negate(b * b))); // (a c - b^2) - k tr^2
}

// The six gradient products of voxels i .. i + lanes - 1 of a row, into products q ...
template <class P>
MCV_HARRIS_INLINE void productsAt(const float* cur, const float* prevRow, const float* nextRow,
  const float* below, const float* above, int i, int im, int ip, const float* scale,
  float* const* out, int q)
{
  const P gx = (load<P>(cur + ip) - load<P>(cur + im)) * splat<P>(scale[0]);
  const P gy = (load<P>(nextRow + i) - load<P>(prevRow + i)) * splat<P>(scale[1]);
  const P gz = (load<P>(above + i) - load<P>(below + i)) * splat<P>(scale[2]);
  store(out[0] + q, gx * gx);
  store(out[1] + q, gx * gy);
  store(out[2] + q, gx * gz);
  store(out[3] + q, gy * gy);
  store(out[4] + q, gy * gz);
  store(out[5] + q, gz * gz);
}

// The six gradient products of row jr of slice z at the tile's columns [x0 - R, x1 + R),
// `stride` floats per channel (a column outside the grid takes the products of the nearest
// border voxel).
template <int W>
MCV_HARRIS_INLINE void productRow(const Setup& s, int z, int jr, int x0, int x1, int stride, float* out)
{
  const int R = W > 0 ? W / 2 : s.radius;
  const int nx = s.nx, ny = s.ny, nz = s.nz;
  const int pw = x1 - x0 + 2 * R; // products per channel
  const std::ptrdiff_t plane = static_cast<std::ptrdiff_t>(nx) * ny;
  const float* cur = s.opacity + z * plane + static_cast<std::ptrdiff_t>(jr) * nx;
  const float* prevRow = cur + static_cast<std::ptrdiff_t>(clampIndex(jr - 1, ny) - jr) * nx;
  const float* nextRow = cur + static_cast<std::ptrdiff_t>(clampIndex(jr + 1, ny) - jr) * nx;
  const float* below = cur + (clampIndex(z - 1, nz) - z) * plane;
  const float* above = cur + (clampIndex(z + 1, nz) - z) * plane;
  float* const channels[Channels] = { out, out + stride, out + 2 * stride, out + 3 * stride,
    out + 4 * stride, out + 5 * stride };
  const int first = x0 - R; // voxel of product 0
  // Products q in [qa, qb) are of voxels inside the grid; the rest replicate the border.
  const int qa = std::max(0, -first), qb = std::min(pw, nx - first);
  // Of those, [ia, ib) are of voxels 1 .. nx-2, which have both x neighbours.
  const int ia = std::min(qb, std::max(qa, 1 - first));
  const int ib = std::max(ia, std::min(qb, nx - 1 - first));
  const auto border = [&](int q) {
    const int i = first + q;
    productsAt<float>(cur, prevRow, nextRow, below, above, i, i > 0 ? i - 1 : 0,
      i + 1 < nx ? i + 1 : nx - 1, s.scale, channels, q);
  };
  for (int q = qa; q < ia; ++q)
  {
    border(q);
  }
  forEachVector(ia, ib, [&](int q, auto lanes) MCV_HARRIS_LAMBDA_INLINE {
    using P = typename decltype(lanes)::type;
    const int i = first + q;
    productsAt<P>(cur, prevRow, nextRow, below, above, i, i - 1, i + 1, s.scale, channels, q);
  });
  for (int q = ib; q < qb; ++q)
  {
    border(q);
  }
  for (int c = 0; c < Channels; ++c)
  {
    float* p = channels[c];
    std::fill(p, p + qa, p[qa]);
    std::fill(p + qb, p + pw, p[qb - 1]);
  }
}

// The taps as vectors (kept in registers: loaded once per row, not once per voxel, which
// the compiler cannot do itself since the outputs might alias them).
template <int W, class P>
struct TapVector
{
  P t[W > 0 ? W : kMaxWidth];
  int width;
  MCV_HARRIS_INLINE TapVector(const Setup& s)
    : width(W > 0 ? W : s.width)
  {
    for (int q = 0; q < (W > 0 ? W : width); ++q)
    {
      t[q] = splat<P>(s.taps[q]);
    }
  }
};

// out[i] = sum_t taps[t] src[t][i]: a chain of fmas from 0 in tap order.
template <int W, class P>
MCV_HARRIS_INLINE void smoothAt(const TapVector<W, P>& taps, const float* const* src, int i, float* out)
{
  P sum = splat<P>(0.f);
  for (int t = 0; t < (W > 0 ? W : taps.width); ++t)
  {
    sum = fmadd(taps.t[t], load<P>(src[t] + i), sum);
  }
  store(out + i, sum);
}

// smoothAt for i < n.
template <int W>
MCV_HARRIS_INLINE void smooth(const Setup& s, const float* const* src, int n, float* out)
{
  const TapVector<W, Pack> wide(s);
  const TapVector<W, float> narrow(s);
  const float* rows[W > 0 ? W : kMaxWidth];
  for (int t = 0; t < wide.width; ++t)
  {
    rows[t] = src[t];
  }
  forEachVector(0, n, [&](int i, auto lanes) MCV_HARRIS_LAMBDA_INLINE {
    using P = typename decltype(lanes)::type;
    if constexpr (std::is_same_v<P, float>)
    {
      smoothAt<W, float>(narrow, rows, i, out);
    }
    else
    {
      smoothAt<W, Pack>(wide, rows, i, out);
    }
  });
}

// The z pass of two consecutive slices at voxels i .. i + lanes - 1 of one channel:
// slices[0 .. width-1] give the first, slices[1 .. width] the second (when `pair`), so a
// pair reads width + 1 slices instead of 2 width.
template <int W, class P>
MCV_HARRIS_INLINE void zPassAt(const TapVector<W, P>& taps, const float* const* slices, bool pair,
  int i, float* first, float* second)
{
  const int width = W > 0 ? W : taps.width;
  P a = splat<P>(0.f), b = splat<P>(0.f);
  P previous = load<P>(slices[0] + i);
  for (int t = 0; t < width; ++t)
  {
    const P next = load<P>(slices[t + 1] + i);
    a = fmadd(taps.t[t], previous, a);
    b = fmadd(taps.t[t], next, b);
    previous = next;
  }
  store(first + i, a);
  if (pair)
  {
    store(second + i, b);
  }
}

// The response at voxels i .. i + lanes - 1 from the six smoothed channels m[c * n + i].
template <class P>
MCV_HARRIS_INLINE void responseAt(const float* m, int n, int i, float k, int plane, float* out)
{
  store(out + i,
    harrisFromTensor<P>(load<P>(m + i), load<P>(m + n + i), load<P>(m + 2 * n + i),
      load<P>(m + 3 * n + i), load<P>(m + 4 * n + i), load<P>(m + 5 * n + i), k, plane));
}

// The x- and y-smoothed products of slice z over tile t, from its ring slot (computed
// into it unless it holds them already). The rows are smoothed along x one at a time into
// a ring of `width` rows, and each output row is smoothed along y as soon as its last row
// is there, so the y pass reads from L1.
template <int W>
MCV_HARRIS_INLINE const float* smoothedSlice(const Setup& s, const Tile& t, Scratch& scratch, int z)
{
  const int R = W > 0 ? W / 2 : s.radius;
  const int width = 2 * R + 1;
  const int nx = t.x1 - t.x0, rows = t.y1 - t.y0;
  const int stride = s.tileX + 2 * R; // floats per channel of the product row
  // Rows of the grid the tile's y pass reads (clamped at the borders).
  const int ya = std::max(0, t.y0 - R), yb = std::min(s.ny, t.y1 + R);
  const std::size_t rowFloats = static_cast<std::size_t>(Channels) * nx;
  const int slot = z % (width + 1);
  float* data = scratch.ring.data() + static_cast<std::size_t>(slot) * rows * rowFloats;
  if (scratch.ringSlice[slot] == z)
  {
    return data;
  }
  const float* src[kMaxWidth];
  int next = t.y0; // the next output row
  for (int jr = ya; jr < yb; ++jr)
  {
    productRow<W>(s, z, jr, t.x0, t.x1, stride, scratch.products.data());
    float* xs = scratch.xSmoothed.data() + static_cast<std::size_t>(jr % width) * rowFloats;
    for (int c = 0; c < Channels; ++c)
    {
      const float* row = scratch.products.data() + static_cast<std::size_t>(c) * stride;
      for (int q = 0; q < width; ++q)
      {
        src[q] = row + q;
      }
      smooth<W>(s, src, nx, xs + static_cast<std::size_t>(c) * nx);
    }
    // Output rows whose last (clamped) row is jr: rows j - R .. j + R are all in the ring.
    for (; next < t.y1 && std::min(next + R, s.ny - 1) <= jr; ++next)
    {
      float* dst = data + static_cast<std::size_t>(next - t.y0) * rowFloats;
      for (int c = 0; c < Channels; ++c)
      {
        for (int q = 0; q < width; ++q)
        {
          src[q] = scratch.xSmoothed.data() +
            static_cast<std::size_t>(clampIndex(next - R + q, s.ny) % width) * rowFloats +
            static_cast<std::size_t>(c) * nx;
        }
        smooth<W>(s, src, nx, dst + static_cast<std::size_t>(c) * nx);
      }
    }
  }
  scratch.ringSlice[slot] = z;
  return data;
}

// One tile, streamed along z two slices at a time: sink.row(z, j) says where the responses
// of row j of slice z (columns x0 .. x1-1) go, and sink.done(z, j, values) is told once
// they are there.
template <int W, class Sink>
void runTile(const Setup& s, const Tile& t, Scratch& scratch, Sink& sink)
{
  const int R = W > 0 ? W / 2 : s.radius;
  const int width = 2 * R + 1;
  const int nx = t.x1 - t.x0;
  const std::size_t rowFloats = static_cast<std::size_t>(Channels) * nx;
  std::fill(scratch.ringSlice.begin(), scratch.ringSlice.end(), -1);
  const TapVector<W, Pack> wide(s);
  const TapVector<W, float> narrow(s);
  const float k = s.k;
  const int plane = s.plane;
  float* first = scratch.tensor.data();
  float* second = first + rowFloats;
  const float* window[kMaxWidth + 1];
  const float* src[kMaxWidth + 1];
  for (int z = t.z0; z < t.z1; z += 2)
  {
    const bool pair = z + 1 < t.z1;
    for (int q = 0; q < width + (pair ? 1 : 0); ++q)
    {
      window[q] = smoothedSlice<W>(s, t, scratch, clampIndex(z - R + q, s.nz));
    }
    if (!pair)
    {
      window[width] = window[width - 1]; // read, not used
    }
    for (int j = t.y0; j < t.y1; ++j)
    {
      for (int c = 0; c < Channels; ++c)
      {
        for (int q = 0; q <= width; ++q)
        {
          src[q] = window[q] + static_cast<std::size_t>(j - t.y0) * rowFloats +
            static_cast<std::size_t>(c) * nx;
        }
        float* a = first + static_cast<std::size_t>(c) * nx;
        float* b = second + static_cast<std::size_t>(c) * nx;
        forEachVector(0, nx, [&](int i, auto lanes) MCV_HARRIS_LAMBDA_INLINE {
          using P = typename decltype(lanes)::type;
          if constexpr (std::is_same_v<P, float>)
          {
            zPassAt<W, float>(narrow, src, pair, i, a, b);
          }
          else
          {
            zPassAt<W, Pack>(wide, src, pair, i, a, b);
          }
        });
      }
      for (int d = 0; d < (pair ? 2 : 1); ++d)
      {
        const float* m = d == 0 ? first : second;
        float* out = sink.row(z + d, j);
        forEachVector(0, nx, [&](int i, auto lanes) MCV_HARRIS_LAMBDA_INLINE {
          responseAt<typename decltype(lanes)::type>(m, nx, i, k, plane, out);
        });
        sink.done(z + d, j, out);
      }
    }
  }
}

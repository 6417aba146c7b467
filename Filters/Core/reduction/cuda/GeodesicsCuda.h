// Isomap's fit on the GPU (Filters/Core/reduction/IsomapEmbedding.cpp): the shortest-path
// distances from every landmark over the reference neighbour graph, and the eigenvalues of
// the landmark MDS Gram matrix.
//
// Plain C++ interface; built only with MCV_ENABLE_CUDA. False with `error` on a CUDA failure
// (the caller computes on the CPU).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace mcv
{
namespace cuda
{

// The largest graph (vertex count) geodesicDistances takes on this device: one source's
// distances (8 B) and two frontier flags (2 B) per vertex must fit in a block's shared
// memory. 0 where no device is usable.
std::size_t geodesicMaxVertices();

// Shortest-path lengths from each of `sources` (count of them) over the graph with n
// vertices in compressed rows (start: n + 1 offsets into `to` and `weight`; edge lengths
// >= 0): dist is count x n, row-major; unreachable vertices get +inf. The lengths are
// summed in double along each path from the source, as Boost's Dijkstra does, and each
// vertex gets the smallest such sum: the same bits as Dijkstra (see GeodesicsCuda.cu).
bool geodesicDistances(std::size_t n, const std::size_t* start, const std::uint32_t* to, const float* weight,
  const std::uint32_t* sources, int count, double* dist, std::string* error);

// Every eigenvalue, ascending, of the symmetric L x L matrix A (column-major; its lower
// triangle is read) by cuSOLVER's divide and conquer (syevd, values only). False with
// `error` on a failure, or where this build has no cuSOLVER.
bool symmetricEigenvalues(const double* A, int L, double* values, std::string* error);

} // namespace cuda
} // namespace mcv

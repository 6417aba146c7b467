// An in-place dense Cholesky factorisation A = L L^T (L lower, written over A's lower
// triangle; the strict upper triangle is neither read nor written), Eigen's blocked LLT, and
// the triangular solves with its factor.
//
// Why separate units: the core is built for baseline x86-64 (SSE2), and there a 500 x 500
// factorisation, the serial step of locally linear landmarks, takes ~3.6 ms; Eigen compiled
// for AVX2 + FMA takes ~1.4 ms and for AVX-512 ~1.1 ms (2-core Xeon dev machine), and its
// solves (two per Lanczos step) ~40% less. DenseCholeskyKernel.cpp is compiled once per
// instruction set and picked at run time where the CPU has it. Its Eigen lives in a
// namespace of its own (mcvEigenAvx2Fma, mcvEigenAvx512), so none of its inline template
// code is shared with (or can replace, at link time) the baseline Eigen of the other files;
// a test (mcvSimdUnitSymbols) checks that the objects define nothing weak outside those
// namespaces.
#pragma once

#include <Eigen/Core>

namespace mcv
{

enum class CholeskyKernel
{
  Auto = 0,     // the widest this CPU and build have
  Baseline = 1, // the core's own Eigen (baseline x86-64)
  Avx2Fma = 2,  // Eigen built for AVX2 + FMA (Baseline where unavailable)
  Avx512 = 3    // Eigen built for AVX-512 F/DQ/VL/BW/CD (else the AVX2 one, else Baseline)
};

// True when this build has the kernel and the CPU runs it (Auto and Baseline: always).
bool choleskyKernelAvailable(CholeskyKernel kernel);

// A: n x n column-major, symmetric, its lower triangle used. Returns false (A's lower
// triangle then undefined) when A is not numerically positive definite.
bool choleskyInPlace(Eigen::Ref<Eigen::MatrixXd> A, CholeskyKernel kernel = CholeskyKernel::Auto);

// x := L^{-1} x, or L^{-T} x when `transposed`; L: the lower triangle of F (n x n), x: n.
void solveWithFactor(const Eigen::Ref<const Eigen::MatrixXd>& F, Eigen::Ref<Eigen::VectorXd> x, bool transposed,
  CholeskyKernel kernel = CholeskyKernel::Auto);

} // namespace mcv

// An in-place dense Cholesky factorisation A = L L^T (L lower, written over A's lower
// triangle; the strict upper triangle is neither read nor written), Eigen's blocked LLT, and
// the triangular solves with its factor.
//
// Why a separate unit: the core is built for baseline x86-64 (SSE2), and there a 500 x 500
// factorisation, the serial step of locally linear landmarks, takes ~3.6 ms; Eigen compiled
// for AVX2 + FMA takes ~1.4 ms (2-core Xeon dev machine). One file, DenseCholeskyAvx2.cpp,
// is compiled with -mavx2 -mfma and picked at run time where the CPU has both. Its Eigen
// lives in a namespace of its own (mcvEigenAvx2Fma), so none of its inline template code is
// shared with (or can replace, at link time) the baseline Eigen of the other files; a test
// (mcvAvx2UnitSymbols) checks that the object defines nothing weak outside that namespace.
#pragma once

#include <Eigen/Core>

namespace mcv
{

enum class CholeskyKernel
{
  Auto = 0,    // AVX2 + FMA where the CPU and the build have it, else Baseline
  Baseline = 1, // the core's own Eigen (baseline x86-64)
  Avx2Fma = 2   // Eigen built for AVX2 + FMA; falls back to Baseline where unavailable
};

// True when this build has the AVX2 + FMA kernel and the CPU runs it.
bool avx2CholeskyAvailable();

// A: n x n column-major, symmetric, its lower triangle used. Returns false (A's lower
// triangle then undefined) when A is not numerically positive definite.
bool choleskyInPlace(Eigen::Ref<Eigen::MatrixXd> A, CholeskyKernel kernel = CholeskyKernel::Auto);

// x := L^{-1} x, or L^{-T} x when `transposed`; L: the lower triangle of F (n x n), x: n.
void solveWithFactor(const Eigen::Ref<const Eigen::MatrixXd>& F, Eigen::Ref<Eigen::VectorXd> x, bool transposed,
  CholeskyKernel kernel = CholeskyKernel::Auto);

} // namespace mcv

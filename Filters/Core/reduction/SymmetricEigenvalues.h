// Every eigenvalue of a dense symmetric matrix, values only, on all the host's threads: the
// spectrum of landmark Isomap's L x L Gram matrix (the variance retained and the eigenvalues
// the result reports need all of them).
//
// Why not Eigen's SelfAdjointEigenSolver alone: its Householder tridiagonalization (the
// O(n^3) part, ~90 % of a values-only solve) is a sequence of single-threaded matrix-vector
// products and rank-2 updates; at L = 500 it took ~45-70 ms of the GPU chain's fit on the
// H200 hosts (docs/benchmarks.md section 5). LAPACK (dsyevd) is no dependency of the
// project, and cuSOLVER is linked only on request (MCV_USE_CUSOLVER). So the same Householder
// reduction is written here with its two O(n^2) steps per column split over OpenMP threads;
// Eigen then takes the tridiagonal matrix (SelfAdjointEigenSolver::computeFromTridiagonal,
// implicit symmetric QL, O(n^2) for the values).
//
// Every element is computed by one thread in a fixed order, so the values do not depend on
// the number of threads (4 or more; with fewer, and below 128 x 128, Eigen's solver runs and
// gives them to rounding: TestSymmetricEigenvalues, within 1e-12 of the spectral radius).
#pragma once

#include <Eigen/Core>

namespace mcv
{

// The eigenvalues of the symmetric `A` (only its lower triangle is read), ascending; false
// when the QL iteration did not converge or `A` holds a non-finite value. On all OpenMP
// threads; Eigen's solver alone below 128 x 128 or with fewer than 4 threads.
bool symmetricEigenvalues(const Eigen::MatrixXd& A, Eigen::VectorXd& ascending);
// The same on `threads` threads (the tests compare thread counts).
bool symmetricEigenvalues(const Eigen::MatrixXd& A, Eigen::VectorXd& ascending, int threads);

} // namespace mcv

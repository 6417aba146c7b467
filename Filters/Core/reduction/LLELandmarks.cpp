#include "LLELandmarks.h"

#include "HugePageBuffer.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Spectra/SymEigsSolver.h>

#include <omp.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace mcv
{

namespace
{
// Relative to the pencil's scale (max diag C / max diag B): far below the wanted
// eigenvalues, so the shift changes nothing but makes C - sigma B positive definite.
constexpr double kShiftInvertSigma = 1e-12;
// Lanczos vectors beyond d kept for the Rayleigh-Ritz step (as in LLEEigen.cpp).
constexpr int kExtraVectors = 3;

// A Z (n x L) row by row: a row holds about 15-30 of the L columns on the brain's features.
// Stored as CSR arrays and read through an Eigen map.
struct SparseRows
{
  std::vector<int> start{ 0 };
  std::vector<int> column;
  std::vector<double> value;
  Eigen::Map<const LandmarkWeights> matrix(Eigen::Index cols) const
  {
    return { static_cast<Eigen::Index>(start.size()) - 1, cols, static_cast<Eigen::Index>(value.size()), start.data(),
      column.data(), value.data() };
  }
  void append(const SparseRows& more)
  {
    const int offset = start.back();
    for (std::size_t i = 1; i < more.start.size(); ++i)
    {
      start.push_back(offset + more.start[i]);
    }
    column.insert(column.end(), more.column.begin(), more.column.end());
    value.insert(value.end(), more.value.begin(), more.value.end());
  }
};

// Rows [first, last) of A Z.
SparseRows multiplyRows(const LLESparseRows& A, const LandmarkWeights& Z,
  Eigen::Index first, Eigen::Index last)
{
  SparseRows out;
  Eigen::VectorXd row = Eigen::VectorXd::Zero(Z.cols()); // one row, scattered
  std::vector<char> used(static_cast<std::size_t>(Z.cols()), 0);
  std::vector<int> columns;
  for (Eigen::Index i = first; i < last; ++i)
  {
    columns.clear();
    for (LLESparseRows::InnerIterator a(A, i); a; ++a)
    {
      for (LandmarkWeights::InnerIterator z(Z, a.col()); z; ++z)
      {
        if (!used[static_cast<std::size_t>(z.col())])
        {
          used[static_cast<std::size_t>(z.col())] = 1;
          columns.push_back(static_cast<int>(z.col()));
        }
        row[z.col()] += a.value() * z.value();
      }
    }
    std::sort(columns.begin(), columns.end());
    for (const int c : columns)
    {
      out.column.push_back(c);
      out.value.push_back(row[c]);
      row[c] = 0.0;
      used[static_cast<std::size_t>(c)] = 0;
    }
    out.start.push_back(static_cast<int>(out.column.size()));
  }
  return out;
}

// A Z, a block of rows per thread (each row's sum in the same order for any thread count).
SparseRows multiply(const LLESparseRows& A, const LandmarkWeights& Z)
{
  std::vector<SparseRows> blocks;
#pragma omp parallel
  {
#pragma omp single
    blocks.resize(static_cast<std::size_t>(omp_get_num_threads()));
    const Eigen::Index t = omp_get_thread_num();
    const Eigen::Index T = static_cast<Eigen::Index>(blocks.size());
    blocks[static_cast<std::size_t>(t)] = multiplyRows(A, Z, Z.rows() * t / T, Z.rows() * (t + 1) / T);
  }
  SparseRows out = std::move(blocks.front());
  for (std::size_t b = 1; b < blocks.size(); ++b)
  {
    out.append(blocks[b]);
  }
  return out;
}

// The entries of a sparse row-major R grouped by column: for column q, at start[q] ..
// start[q + 1], the positions e of its entries in R's arrays (rows ascending) and the end of
// each one's row.
struct EntriesByColumn
{
  std::vector<int> start, entry, rowEnd;
  template <typename Rows>
  explicit EntriesByColumn(const Rows& R)
    : start(static_cast<std::size_t>(R.cols()) + 1, 0)
    , entry(static_cast<std::size_t>(R.nonZeros()))
    , rowEnd(entry.size())
  {
    const int* inner = R.innerIndexPtr();
    const int* outer = R.outerIndexPtr();
    for (int e = 0; e < outer[R.rows()]; ++e)
    {
      ++start[static_cast<std::size_t>(inner[e]) + 1];
    }
    for (std::size_t q = 0; q + 1 < start.size(); ++q)
    {
      start[q + 1] += start[q];
    }
    std::vector<int> next(start.begin(), start.end() - 1);
    for (Eigen::Index i = 0; i < R.rows(); ++i)
    {
      for (int e = outer[i]; e < outer[i + 1]; ++e)
      {
        const int slot = next[static_cast<std::size_t>(inner[e])]++;
        entry[static_cast<std::size_t>(slot)] = e;
        rowEnd[static_cast<std::size_t>(slot)] = outer[i + 1];
      }
    }
  }
};

// Adds s R^T R to the lower part of column q of S: for every row i holding column q, its
// entries p >= q (R's rows sorted by column). Rows in ascending order, so each entry is
// summed in the same order whichever thread owns the column. The pairs of one row are few:
// the cost is the sum over rows of nnz^2 / 2, and the writes stay in one column (in L1),
// where a row-by-row pass scattered them over the whole matrix, missing L2 on most adds
// (a sparse-times-sparse product, with its symbolic pass and sparse result, is slower still).
template <typename Rows>
void addLowerGramColumn(const Rows& R, const EntriesByColumn& byColumn, double s, Eigen::Index q, double* column)
{
  const int* inner = R.innerIndexPtr();
  const double* value = R.valuePtr();
  for (int slot = byColumn.start[static_cast<std::size_t>(q)]; slot < byColumn.start[static_cast<std::size_t>(q) + 1];
       ++slot)
  {
    const int e = byColumn.entry[static_cast<std::size_t>(slot)];
    const double vq = s * value[e];
    for (int p = e; p < byColumn.rowEnd[static_cast<std::size_t>(slot)]; ++p)
    {
      column[inner[p]] += value[p] * vq;
    }
  }
}

// S (L x L, not initialised) = the lower triangle of s1 R1^T R1 + s2 R2^T R2, a column per
// task (the thread that owns a column also first touches, i.e. page faults, it).
template <typename Rows1, typename Rows2>
void lowerGram(const Rows1& R1, double s1, const Rows2& R2, double s2, Eigen::Ref<Eigen::MatrixXd> S)
{
  const EntriesByColumn columns1(R1), columns2(R2);
#pragma omp parallel for schedule(dynamic, 8)
  for (Eigen::Index q = 0; q < S.cols(); ++q)
  {
    S.col(q).setZero();
    addLowerGramColumn(R1, columns1, s1, q, S.col(q).data());
    addLowerGramColumn(R2, columns2, s2, q, S.col(q).data());
  }
}

// y_i = R_i . x for every row i of the sparse row-major R: an OpenMP work-sharing loop for
// the enclosing parallel region (its end is a barrier).
void rowDots(const LandmarkWeights& R, const double* x, double* y)
{
  const int* outer = R.outerIndexPtr();
  const int* inner = R.innerIndexPtr();
  const double* value = R.valuePtr();
#pragma omp for schedule(static)
  for (Eigen::Index i = 0; i < R.rows(); ++i)
  {
    double sum = 0.0;
    for (int e = outer[i]; e < outer[i + 1]; ++e)
    {
      sum += value[e] * x[inner[e]];
    }
    y[i] = sum;
  }
}

// R V for a sparse row-major R (n x L) and a dense V (L x m), rows split over the threads.
template <typename Rows>
Eigen::MatrixXd multiplyByRows(const Rows& R, const Eigen::MatrixXd& V)
{
  Eigen::MatrixXd Y(R.rows(), V.cols());
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < R.rows(); ++i)
  {
    Y.row(i) = R.row(i) * V;
  }
  return Y;
}

// Shift-invert as a standard symmetric problem. With C - sigma B = F F^T (Cholesky) and
// x = F^{-T} u, C x = lambda B x becomes T u = mu u, T = F^{-1} B F^{-T}, mu = 1 / (lambda -
// sigma): the smallest lambda are the largest mu, and Lanczos needs plain dot products
// (Spectra's generalized mode takes B-inner products: a B product more per step). B x is
// Z^T (Z x): B itself is never formed. The constant (C 1 = 0) maps to u0 = F^T 1 with
// mu = 1 / |sigma|, which would dwarf the wanted ones: the operator is P T P with
// P = I - u0 u0^T / |u0|^2.
class DeflatedShiftInvert
{
public:
  using Scalar = double;
  // F: the Cholesky factor in the lower triangle (Eigen's LLT, in place).
  DeflatedShiftInvert(const Eigen::Ref<const Eigen::MatrixXd>& F, const LandmarkWeights& Z)
    : F_(F)
    , Z_(Z)
    , Zt_(Z.transpose())
    , constant_((F.triangularView<Eigen::Lower>().transpose() * Eigen::VectorXd::Ones(Z.cols())).normalized())
    , work_(Z.cols())
    , points_(Z.rows())
  {
  }
  Eigen::Index rows() const { return Z_.cols(); }
  Eigen::Index cols() const { return Z_.cols(); }
  void perform_op(const double* x, double* y) const
  {
    Eigen::Map<const Eigen::VectorXd> in(x, rows());
    Eigen::Map<Eigen::VectorXd> out(y, rows());
    work_ = in - constant_ * constant_.dot(in);
    F_.triangularView<Eigen::Lower>().transpose().solveInPlace(work_); // F^{-T}
    // B work = Z^T (Z work), both products as row-by-row dot products (Zt_: Z^T by rows)
    // split over the threads, so each entry is summed in the same order for any count.
#pragma omp parallel
    {
      rowDots(Z_, work_.data(), points_.data());
      rowDots(Zt_, points_.data(), out.data());
    }
    F_.triangularView<Eigen::Lower>().solveInPlace(out); // F^{-1}
    out -= constant_ * constant_.dot(out);
  }

private:
  const Eigen::Ref<const Eigen::MatrixXd> F_;
  const LandmarkWeights& Z_;
  const LandmarkWeights Zt_;
  const Eigen::VectorXd constant_;
  mutable Eigen::VectorXd work_, points_;
};
} // namespace

LLEBottomEigen lleLandmarkEigenvectors(const LLESparseRows& A, const LandmarkWeights& Z, int d)
{
  LLEBottomEigen r;
  const Eigen::Index n = Z.rows();
  const Eigen::Index L = Z.cols();
  if (d < 1 || L < d + 2 || A.rows() != n || A.cols() != n)
  {
    r.error = "need d >= 1, at least d + 2 landmarks and A of Z's row count";
    return r;
  }
  // The pencil (C, B) = ((A Z)^T A Z, Z^T Z). Only C - sigma B is formed (and factored in
  // place): one L x L matrix, as fresh memory costs page faults as well as the time to fill it.
  const SparseRows AZrows = multiply(A, Z);
  const Eigen::Map<const LandmarkWeights> AZ = AZrows.matrix(L);
  // max diag C / max diag B: the column sums of squares of A Z and Z.
  const Eigen::RowVectorXd ones = Eigen::RowVectorXd::Ones(n);
  const double scale =
    std::max(1e-300, (ones * AZ.cwiseAbs2()).maxCoeff() / (ones * Z.cwiseAbs2()).maxCoeff());
  const double sigma = -kShiftInvertSigma * scale;
  HugePageBuffer storage(static_cast<std::size_t>(L * L));
  Eigen::Map<Eigen::MatrixXd> S(storage.data(), L, L);
  lowerGram(AZ, 1.0, Z, -sigma, S);
  // Plain Eigen LLT: Eigen builds for AVX2 / AVX-512 picked at run time made no difference
  // a user would see on the whole LLE fit (docs/benchmarks.md, section 9).
  if (Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>>(S).info() != Eigen::Success) // S becomes F (lower triangle)
  {
    r.error = "the Cholesky factorisation of C - sigma B failed";
    return r;
  }
  const int nev = static_cast<int>(std::min<Eigen::Index>(d + kExtraVectors, L - 2));
  const int ncv = static_cast<int>(std::min<Eigen::Index>(L - 1, std::max(2 * nev + 1, 20)));
  Eigen::MatrixXd V;
  try
  {
    DeflatedShiftInvert op(S, Z);
    Spectra::SymEigsSolver<DeflatedShiftInvert> eigs(op, nev, ncv);
    eigs.init();
    eigs.compute(Spectra::SortRule::LargestAlge, 300, 1e-10);
    if (eigs.info() != Spectra::CompInfo::Successful)
    {
      r.error = "shift-invert Lanczos on the landmark pencil did not converge";
      return r;
    }
    V = S.triangularView<Eigen::Lower>().transpose().solve(eigs.eigenvectors()); // x = F^{-T} u
  }
  catch (const std::exception& ex) // an inner eigensolve
  {
    r.error = ex.what();
    return r;
  }

  // Centred over the n points (Y = Z V; Z's rows sum to 1, so a constant taken from V is
  // taken from Y; the deflation made the means ~0 already), then Rayleigh-Ritz with the
  // exact pencil: V^T C V = (A Z V)^T (A Z V), V^T B V = (Z V)^T (Z V).
  Eigen::MatrixXd Y = multiplyByRows(Z, V);
  const Eigen::RowVectorXd means = Y.colwise().mean();
  V.rowwise() -= means;
  Y.rowwise() -= means;
  const Eigen::MatrixXd AY = multiplyByRows(AZ, V);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ritz(AY.transpose() * AY, Y.transpose() * Y);
  if (ritz.info() != Eigen::Success)
  {
    r.error = "the Rayleigh-Ritz step on the landmark pencil failed";
    return r;
  }
  r.values = ritz.eigenvalues().head(d); // ascending
  r.vectors = Y * ritz.eigenvectors().leftCols(d);
  return r;
}

} // namespace mcv

// Dimensionality reduction of per-voxel feature vectors to a small (2D/3D) domain the
// user paints transfer functions in (dissertation chapter 5).
//
// Scale: the embedding is fitted on a reference sample of M voxels; every other voxel is
// placed by its 3 nearest reference vectors in feature space with barycentric weights
// w = argmin |x - sum w_i x_i|^2, sum w_i = 1, and y = sum w_i y_i (section 5.4.2).
#pragma once

#include "Communicator.h"
#include "Device.h"
#include "FeatureRows.h"
#include "GridPiece.h"
#include "HalfCoordinates.h"
#include "ImageGrid.h"
#include "ReductionModel.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace mcv
{

enum class ReductionMethod
{
  PCA = 0,
  Isomap = 1, // landmark Isomap: kNN graph, shortest paths from L landmarks, landmark MDS
  LLE = 2,    // locally linear embedding: sparse (I-W)^T(I-W), smallest eigenvectors (on L
              // landmarks by default: LLELandmarks.h)
  UMAP = 3    // fuzzy simplicial set of the kNN graph, spectral start, SGD layout (UMAPEmbedding.h)
};

// n rows (voxels) x d columns (features), row-major, float32: the layout of a VTK
// multi-component array, so the filter passes its pointer without a copy.
struct FeatureMatrix
{
  const float* data = nullptr;
  std::size_t rows = 0;
  int cols = 0;
  const float* row(std::size_t i) const { return data + i * static_cast<std::size_t>(cols); }
};

struct ReductionOptions
{
  // ---- The method and its parameters (ReductionMethods.h: which method uses which) --------
  ReductionMethod method = ReductionMethod::PCA;
  int outputDimension = 3;              // 2 or 3
  // Neighbour-graph methods (Isomap, LLE, UMAP):
  int numberOfNeighbors = 50;           // K of the neighbourhood graph
  int numberOfLandmarks = 500;          // L of landmark Isomap and LLE (>= M: exact)
  // UMAP alone:
  double minimumDistance = 0.1;         // min_dist of the layout, in [0, 1]
  int numberOfEpochs = 0;               // SGD epochs; 0: 500 up to 10000 points, else 200

  // ---- The reference sample, where it runs, progress -------------------------------------
  std::size_t referenceSampleSize = 10000; // M; >= the voxels (of all processes) fits on all
  std::uint64_t randomSeed = 0;         // same seed, same result
  Device device = Device::Auto;         // the out-of-sample step (touches every voxel),
                                        // Isomap's fit (graph search, shortest paths, MDS
                                        // spectrum) and UMAP's layout (the SGD epochs of its
                                        // fit); a GPU that fails falls back to the CPU with a
                                        // warning
  int trustworthinessNeighbors = 10;    // k of the trustworthiness measure
  std::size_t trustworthinessSample = 2000; // points it is measured on (from the reference)
  // Optional progress: stage name and overall fraction in [0,1].
  std::function<void(const char* stage, double fraction)> progress;

  // ---- Where the results go ------------------------------------------------------------
  // Optional: rows x outputDimension floats the caller owns (the output VTK array's memory),
  // where the coordinates are written; ReductionResult::coordinates then stays empty. Saves
  // a zero-filled buffer and a copy as large as the output (85 MB for the 7.1 M-voxel brain
  // in 3D). Undefined where the reduction fails.
  float* coordinatesOutput = nullptr;
  // Optional instead: rows x outputDimension binary16 values (HalfCoordinates.h) the caller
  // owns, for float16 coordinates at half the memory. The placement writes into a float
  // scratch of kHalfPlacementRows rows (HalfCoordinates.h; 12 MiB in 3D) and rounds each
  // chunk into it, so no float copy of the whole output exists. A coordinate beyond
  // float16's range (|x| > 65504) fails the reduction. Not together with coordinatesOutput.
  std::uint16_t* coordinatesHalfOutput = nullptr;
  // Optional, one byte per row (features.rows): rows marked 0 (the background of a volume:
  // the Foreground array of MultichannelFeatures) are never drawn into the reference
  // sample, so the embedding, its spectrum and trustworthiness describe the foreground.
  // They are still placed out of sample like every row. Null: every row may be drawn. A
  // mask that marks no row at all is ignored (warning).
  const unsigned char* sampleMask = nullptr;

  // ---- A volume split over processes (MPI) ---------------------------------------------
  // Split over processes (Communicator.h): every process calls reduceDimension with its own
  // rows and the same options, and all get the answer one process would give for the whole
  // (same reference sample, embedding and coordinates for the same seed). Null, or a
  // communicator of one process: serial.
  const Communicator* communicator = nullptr;
  // Where the rows lie (GridPiece.h): when piece.wholeDims is set, the rows are the voxels
  // of `block` (rows == block.voxelCount(), x fastest), of which the process owns those the
  // piece says; statistics and the sample count owned voxels only. Left at the defaults,
  // the rows are plain rows, every one owned, the processes' rows one after another in rank
  // order (global index = rows of the lower ranks + row).
  GridPiece piece;
  ImageGrid block;
  // Optional, with piece and block: the box of the block (block voxel indices, inclusive)
  // whose coordinates the output holds, x fastest: a split run's output extent without its
  // ghost layers, so that coordinatesOutput / coordinatesHalfOutput / result.coordinates
  // are sized for the piece, not for the block, and no block-sized array has to be cropped
  // afterwards. The rows outside are placed with their chunk but not kept. Left at the
  // defaults (outputHi < outputLo): every row.
  std::array<int, 3> outputLo{ 0, 0, 0 };
  std::array<int, 3> outputHi{ -1, -1, -1 };
  // The fit of a time series (with fitOnly): the rows are timeSteps volumes one after
  // another, each laid out as above (rows == timeSteps x block.voxelCount() with a grid;
  // the steps' rows in order without one), and step s's voxels have global index
  // s x (whole voxels) + voxel, so the reference sample is drawn across the steps with the
  // keys, strata and duplicates rule of one volume, the same for any split.
  int timeSteps = 1;

  // ---- Models: apply one, or keep the fit -----------------------------------------------
  // Optional: apply this model (ReductionModel.h) instead of fitting: no statistics, no
  // sample, no fit; the rows are placed with the model's references (or projected on its PCA
  // basis). The rows must have the model's featureColumns columns, in its order; method,
  // outputDimension and the sample's options are the model's, not these.
  const ReductionModel* model = nullptr;
  // Optional: where a fit stores its model (every process gets the same one).
  ReductionModel* fittedModel = nullptr;
  // Stop after the fit (fittedModel, spectrum, trustworthiness): no row is placed and the
  // coordinates outputs are left untouched. For a fit whose model other rows will use.
  bool fitOnly = false;
  // Optional, with `model`: one float per output row (like coordinatesOutput), each row's
  // distance to the nearest reference over the model's referenceRadius (ModelDistance.h);
  // rows beyond kOutOfModelRatio are counted in ReductionResult::outOfModelVoxels.
  float* modelDistanceOutput = nullptr;
};

struct ReductionResult
{
  std::string error;                 // non-empty: nothing else is meaningful
  std::vector<std::string> warnings; // one line each
  std::vector<float> coordinates;    // rows x outputDimension, row-major (empty when
                                     // options.coordinatesOutput or coordinatesHalfOutput
                                     // received them)
  int outputDimension = 0;
  std::vector<double> eigenvalues;   // spectrum, descending (PCA: covariance; Isomap: MDS;
                                     // LLE: the smallest non-trivial eigenvalues, ascending;
                                     // UMAP: its spectral start's Laplacian eigenvalues, ascending)
  double varianceRetained = 0.0;     // top-d eigenvalues / sum of positive ones (PCA, Isomap)
  double trustworthiness = 0.0;      // on a sample of the reference points, in [0,1];
                                     // NaN when not computed (trustworthinessSample 0,
                                     // or a sample of no more than 2k points)
  std::vector<int> usedColumns;      // features kept (zero-variance ones are dropped)
  std::vector<std::int64_t> referenceIndices; // rows the embedding was fitted on: global
                                              // indices (voxels of the whole volume)
  std::size_t sampledVoxels = 0;     // voxels (all processes) the sample was drawn from:
                                     // those sampleMask marks, or all of them
  Device deviceUsed = Device::CPU;
  bool modelApplied = false;          // placed with options.model (no fit ran)
  std::size_t outOfModelVoxels = 0;   // with modelDistanceOutput: output rows (all processes)
                                      // beyond kOutOfModelRatio
  double fitMs = 0, placeMs = 0, totalMs = 0;
  bool ok() const { return error.empty(); }
};

// The capability's one entry point. Collective when options.communicator spans several
// processes: errors, warnings, the spectrum and trustworthiness are the same on all of them;
// coordinates are each process's own rows.
ReductionResult reduceDimension(const FeatureMatrix& features, const ReductionOptions& options);

// The same on rows read block by block (FeatureRows.h): the fused path, whose features are
// computed from the channels a block at a time (FeatureBricks.h) and never stored whole.
// Statistics, strata and placement each walk the blocks once; the sample gathers its few
// rows. Progress is reported between blocks of the placement.
ReductionResult reduceDimension(FeatureRows& features, const ReductionOptions& options);

} // namespace mcv

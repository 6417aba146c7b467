// UMAP's layout step (McInnes, Healy & Melville 2018, section 3.2; umap-learn 0.5.3's
// optimize_layout_euclidean): stochastic gradient descent of the fuzzy-set cross-entropy
// between the graph's weights w_ij and the low-dimensional similarities
// q_ij = 1 / (1 + a |y_i - y_j|^(2b)), with negative sampling:
//  - edge e is sampled every epochs_per_sample[e] = max w / w_e epochs; a sample pulls its
//    two ends together (attraction, both move) and pushes its head away from 5 vertices
//    drawn uniformly (repulsion, gamma = 1, only the head moves);
//  - every gradient component is clipped to [-4, 4]; the learning rate is 1, decaying
//    linearly to 0 over the epochs.
//
// Deterministic in parallel, and the same for every thread count: the vertices are split
// into kLayoutBlocks seeded blocks (stored block by block) and the edges grouped by the
// pair of blocks they join. An epoch runs kLayoutBlocks rounds; a round is a set of pairs
// that share no block (a round-robin tournament, plus one round of the within-block pairs),
// so its pairs run in parallel without touching the same vertex, each in a fixed edge
// order with its own random stream (seed, epoch, pair). A thread waits only for the
// two blocks of its next pair to finish the round before, and for the others at the end of
// an epoch. The negative samples read the positions as they were at the start of the
// epoch (a copy): a repelling vertex may be moved by another pair in the same round.
// Every 10 epochs the layout runs on all threads or on one, whichever took less time per
// epoch when last tried (a machine busy with other work can leave two threads waiting for
// each other): the same bits either way, so only the time depends on it.
// Within a task the edges go by their rank in the row, then by row (consecutive samples
// have different heads). Where the CPU has AVX2, up to eight consecutive due samples that
// share no vertex run side by side, one per lane, with the same bits as the portable loop
// that runs them one after the other (LayoutOptions::vectorised). The vertices of a sample's
// negative samples come from its own counter-based stream (a hash of seed, epoch, edge and
// draw), so the eight lanes draw them at once.
//
// Differences from umap-learn's sequential pass, all within the noise of SGD (the
// trustworthiness of the result matches: docs/benchmarks.md): the order of the updates;
// that staleness (at most one epoch); the negative samples of one positive sample are all
// evaluated at the head's position after the attraction and their pushes applied together
// (umap-learn moves the head after each one); and the two gradient coefficients come from a
// table of the squared distance (relative error < 4e-4, UMAPLayout.cpp) instead of powf;
// the negative samples' vertices come from a hash per sample instead of one sequential
// generator.
//
// optimizeLayout is the one function a GPU kernel would replace (same problem, same
// options, the layout in place).
#pragma once

#include "Embedding.h"

#include <cstdint>
#include <vector>

namespace mcv
{

struct FuzzyGraph;

// a, b of q(d) = 1 / (1 + a d^(2b)) fitted by least squares (Levenberg-Marquardt from
// (1, 1), as scipy's curve_fit in umap-learn's find_ab_params) to the target
// 1 for d < minDist, exp(-(d - minDist) / spread) beyond, at 300 points of [0, 3 spread].
struct CurveParameters
{
  double a = 0, b = 0;
  bool converged = false;
};
CurveParameters fitCurveParameters(double minDist, double spread = 1.0);

// umap-learn's default number of epochs: 500 up to 10000 points, 200 beyond.
int defaultEpochs(std::size_t points);

constexpr int kLayoutBlocks = 16;

struct LayoutOptions
{
  int epochs = 500;
  double a = 1.577, b = 0.8951; // fitCurveParameters(0.1)
  double gamma = 1.0;           // repulsion strength
  double initialAlpha = 1.0;    // learning rate
  int negativeSampleRate = 5;
  std::uint64_t seed = 0;
  // Eight samples at a time (AVX2, where the CPU has it): the same bits as the portable
  // loop that false selects (a test compares them).
  bool vectorised = true;
  StageProgress progress; // called between epochs, from the calling thread
};

// Whether this CPU runs the eight-lane samples (LayoutOptions::vectorised).
bool layoutIsVectorised();

// graph: the fuzzy simplicial set (weights in (0, 1]); Y: n x d (d = 2 or 3) start
// positions, replaced by the layout. OpenMP inside every epoch (or one thread, above).
void optimizeLayout(const FuzzyGraph& graph, const LayoutOptions& options, RowMatrixF& Y);

} // namespace mcv

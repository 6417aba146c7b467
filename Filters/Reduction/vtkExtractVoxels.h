/**
 * @class   vtkExtractVoxels
 * @brief   the voxels of a volume at given global voxel ids, as points, on any number of
 *          processes.
 *
 * Input: a vtkImageData. VoxelIds lists voxels by their global id, the index in the whole
 * extent: i + nx (j + ny k) with (i, j, k) counted from the first voxel of the whole extent
 * and (nx, ny, nz) its dimensions, the VoxelId of ReducedDomain. The output is a
 * vtkPolyData with one vertex per listed voxel at the voxel's world position (origin,
 * spacing and direction matrix applied), with
 *
 * - copies of the input's point arrays at that voxel (exact values: no interpolation, so
 *   float16 coordinates stored as uint16 bits keep their bits),
 * - `VoxelId` (vtkIdType, the global id) and `VoxelIJK` (int, 3 components, the index
 *   counted from the first voxel of the whole extent),
 * - field data `Origin`, `Spacing` (3 doubles each), `Direction` (9, row major) and
 *   `WholeExtent` (6 ints) of the volume, so that a client can place any other voxel.
 *
 * Split runs (mpiexec pvbatch --mpi, an MPI pvserver): each process takes its piece of the
 * volume (mcvPieces.h) and outputs the listed voxels it owns, so every voxel comes out of
 * exactly one process although neighbouring pieces share a layer of points; gathered
 * (servermanager.Fetch, a representation), the output holds each listed voxel once, in
 * list order within each process. An id outside the volume is an error (the output is
 * empty). A listed id repeated is output as often as it is listed.
 *
 * This replaces a one-voxel Extract Subset (which, fetched under MPI, comes back empty for a
 * voxel that the first process does not hold) and an ID selection of point ids (which
 * counts ids within each process's piece, not over the whole volume).
 */

#ifndef vtkExtractVoxels_h
#define vtkExtractVoxels_h

#include "mcvFiltersReductionModule.h" // for export macro
#include "vtkMultichannelAlgorithm.h"

#include <vector> // for std::vector

class vtkPolyData;

class MCVFILTERSREDUCTION_EXPORT vtkExtractVoxels : public vtkMultichannelAlgorithm
{
public:
  static vtkExtractVoxels* New();
  vtkTypeMacro(vtkExtractVoxels, vtkMultichannelAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** The output is polydata (the base's GetOutput would cast it to image data). */
  vtkPolyData* GetOutput();
  ///@}

  ///@{
  /** The global voxel ids to extract, in order (ServerManager: VoxelIds). */
  void SetNumberOfVoxelIds(int count);
  void SetVoxelId(int index, vtkIdType id);
  int GetNumberOfVoxelIds();
  vtkIdType GetVoxelId(int index);
  ///@}

protected:
  vtkExtractVoxels();
  ~vtkExtractVoxels() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  // Split over processes without ghost layers: each voxel is read where it is owned.
  int GetSplitGhostLayers() override { return 0; }
  int RequestMultichannelData(
    vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkExtractVoxels(const vtkExtractVoxels&) = delete;
  void operator=(const vtkExtractVoxels&) = delete;

  std::vector<vtkIdType> VoxelIds;
};

#endif

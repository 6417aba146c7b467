// What the checked readers of this module (vtkCheckedNIFTIImageReader,
// vtkCheckedMetaImageReader, vtkCheckedTIFFReader) share: the size and memory checks they
// make before anything is allocated, and the way they refuse a file: one error that names
// the file and the problem, and an empty output (never a zero-filled or stale volume).
#ifndef CheckedReading_h
#define CheckedReading_h

#include <cstdint>    // for std::int64_t
#include <functional> // for std::function
#include <string>     // for std::string

class vtkAlgorithm;
class vtkObject;
class vtkImageReader2;
class vtkInformation;
class vtkInformationVector;

namespace mcv
{

// Size of the file in bytes; -1 when it cannot be opened.
std::int64_t fileBytes(const std::string& name);

// Bytes of the gzip or zlib stream that starts at `offset` of the file, once decompressed
// (gzip members one after the other are counted together, as gzread reads them). Reading
// the whole stream is the only way to know: a truncated stream has no trailer to trust.
// -1 with `error` set when the file cannot be opened or the stream is corrupt or ends early.
// ZlibOrGzip: a stream must be there (MetaImage's CompressedData). GzipOrPlain: as gzopen
// reads (and vtkNIFTIImageReader with it): gzip when the file starts so, else plain bytes.
enum class Compression
{
  ZlibOrGzip,
  GzipOrPlain
};
std::int64_t inflatedBytes(
  const std::string& name, std::int64_t offset, Compression expected, std::string& error);

// "" when each of the `n` spacings is finite and non-zero; else, e.g., "has spacing nan along
// axis 1 (ElementSpacing in its header must be finite and non-zero)", `field` naming
// where the spacing comes from.
std::string checkSpacing(const double* spacing, int n, const std::string& field);

// "" when `present` bytes hold the `voxels` (of `bytesPerVoxel` bytes each, from byte
// `offset` on) that a header promises; else "is truncated: its header promises N bytes (V
// voxels of B bytes from offset O), <holder> P", holder being e.g. "the file holds".
std::string checkPresent(double voxels, double bytesPerVoxel, double offset, std::int64_t present,
  const std::string& holder);

// "" when the volume fits in the memory this process may still use (MemoryBudget); else
// "needs 6.8 GiB for its N voxels, but only 1.2 GiB is available".
std::string checkFitsInMemory(double voxels, double bytesPerVoxel);

// RequestInformation of a checked reader. `readHeader` runs the reader's own
// RequestInformation and its checks (in the order the reader needs) and returns the problem
// found, "" if none; an error that the reader reports meanwhile is a problem too. A problem
// is reported as "<what> <problem>. Nothing is read." and the output emptied. Returns 1 when
// the file may be read.
int checkedRequestInformation(vtkAlgorithm* reader, vtkInformationVector* outputVector,
  const std::string& what, const std::function<std::string()>& readHeader);

// Runs `run` with the errors that `object` reports caught instead of printed; returns their
// text ("" when none), each without the "ERROR: In file, line N / Class (0x...): " head.
std::string caughtErrors(vtkObject* object, const std::function<void()>& run);
// RequestData of a checked reader: nothing when the header was `refused`; else `readData`
// (the reader's own RequestData), and an error that the reader reports while reading (a
// corrupt strip, a read that failed) refuses the whole volume. Returns 1 when it was read.
int checkedRequestData(vtkAlgorithm* reader, vtkInformationVector* outputVector,
  const std::string& what, bool refused, const std::function<int()>& readData);

// Time series. ParaView reads a list of files (or the GUI's group "vol_0.nii.gz,
// vol_1.nii.gz, ...") through a vtkFileSeriesReader around the checked reader: one file per
// time step, on the grid the first file announced (the output information's whole extent,
// spacing and origin). "" when `reader`'s header, just read, gives that grid and that point
// type (always so for a single file); else the problem, naming the first file:
// "has 10 x 10 x 10 voxels, spacing 1 1 1, origin 0 0 0, unsigned char x 1, but the first file
// of its time series '.../vol_0.nii.gz' has ...: the files of a time series must share one grid".
std::string checkSeriesGrid(vtkImageReader2* reader, vtkInformation* outInfo);

// The name of the array a checked reader delivers: its file's stem ("ch2" for ch2.nii.gz),
// or in a time series of several files the series' name after its first file ("vol" for
// vol_0.nii.gz, vol_1.nii.gz, ...), so that every time step has the same array; "" when
// the name would be empty.
std::string channelArrayName(vtkInformation* outInfo, const std::string& fileName);

// Names the point scalars of the image in `outputVector` `name` (nothing when either is
// empty).
void nameScalars(vtkInformationVector* outputVector, const std::string& name);

// RequestData of a checked reader that may read one file of a time series (the NIfTI and
// MetaImage readers): the file's grid checked against the series' (checkSeriesGrid), then
// checkedRequestData, then the array named after the file (channelArrayName, nameScalars).
int checkedSeriesRequestData(vtkImageReader2* reader, vtkInformationVector* outputVector,
  const std::string& what, bool refused, const std::function<int()>& readData);

} // namespace mcv

#endif

#include "vtkOMEZarrReader.h"

#include "CheckedReading.h"
#include "OMEZarrMetadata.h"
#include "ZarrArray.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTypeInt64Array.h"
#include "vtksys/SystemTools.hxx"

#include <algorithm>
#include <cstring>
#include <set>
#include <vector>

vtkStandardNewMacro(vtkOMEZarrReader);

namespace
{
// The VTK type of a Zarr element type.
int vtkTypeOf(const mcv::zarr::ArrayMeta& a)
{
  switch (a.ItemSize)
  {
    case 1:
      return a.Kind == 'u' ? VTK_UNSIGNED_CHAR : VTK_SIGNED_CHAR;
    case 2:
      return a.Kind == 'u' ? VTK_UNSIGNED_SHORT : VTK_SHORT;
    case 4:
      return a.Kind == 'f' ? VTK_FLOAT : (a.Kind == 'u' ? VTK_UNSIGNED_INT : VTK_INT);
    default:
      return a.Kind == 'f' ? VTK_DOUBLE : (a.Kind == 'u' ? VTK_UNSIGNED_LONG_LONG : VTK_LONG_LONG);
  }
}

std::string joinPath(const std::string& folder, const std::string& name)
{
  if (folder.empty() || folder.back() == '/')
  {
    return folder + name;
  }
  return folder + "/" + name;
}

std::string shapeText(const std::vector<std::int64_t>& shape)
{
  std::string s = "[";
  for (std::size_t i = 0; i < shape.size(); ++i)
  {
    s += (i ? ", " : "") + std::to_string(shape[i]);
  }
  return s + "]";
}

// Channel names: the omero labels where given, else C1..Cn; a name already taken gets
// " (2)", " (3)", ... so that every point array has its own name.
std::vector<std::string> channelNames(
  const std::vector<mcv::zarr::Channel>& channels, std::int64_t count)
{
  std::vector<std::string> names;
  std::set<std::string> taken;
  for (std::int64_t c = 0; c < count; ++c)
  {
    std::string base = c < static_cast<std::int64_t>(channels.size()) ? channels[c].Label : "";
    if (base.empty())
    {
      base = "C" + std::to_string(c + 1);
    }
    std::string name = base;
    for (int k = 2; taken.count(name); ++k)
    {
      name = base + " (" + std::to_string(k) + ")";
    }
    taken.insert(name);
    names.push_back(name);
  }
  return names;
}
} // namespace

struct vtkOMEZarrReader::Internals
{
  bool Refused = true;
  mcv::zarr::ImageMeta Image;
  mcv::zarr::ArrayMeta Array; // the level read
  int Level = -1;
  // Axis indices in the array (-1: the image has no such axis).
  int T = -1, C = -1, Z = -1, Y = -1, X = -1;
  std::int64_t Channels = 1;
  std::vector<double> TimeSteps;
  std::vector<std::string> Names;
  double Spacing[3] = { 1, 1, 1 };
  double Origin[3] = { 0, 0, 0 };
  int Whole[6] = { 0, -1, 0, -1, 0, -1 };

  std::string LevelName(int level) const
  {
    return "resolution level " + std::to_string(level) + " ('" +
      this->Image.Levels[level].Path + "')";
  }
};

//------------------------------------------------------------------------------
vtkOMEZarrReader::vtkOMEZarrReader()
  : Impl(new Internals)
{
}

//------------------------------------------------------------------------------
vtkOMEZarrReader::~vtkOMEZarrReader() = default;

//------------------------------------------------------------------------------
std::string vtkOMEZarrReader::Describe() const
{
  return std::string("OME-Zarr folder '") + (this->FileName ? this->FileName : "") + "'";
}

//------------------------------------------------------------------------------
int vtkOMEZarrReader::CanReadFile(const char* name)
{
  if (!name || !vtksys::SystemTools::FileIsDirectory(name))
  {
    return 0;
  }
  for (const char* marker : { ".zattrs", ".zgroup", ".zarray" })
  {
    if (vtksys::SystemTools::FileExists(joinPath(name, marker), true))
    {
      return 1;
    }
  }
  return 0;
}

//------------------------------------------------------------------------------
int vtkOMEZarrReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  Internals& in = *this->Impl;
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  this->LevelRead = -1;
  in.Level = -1;
  const std::string folder = this->FileName ? this->FileName : "";

  // Reads the .zarray of `level` into in.Array and checks it against the axes.
  auto readLevel = [&](int level) -> std::string {
    const std::string path = joinPath(joinPath(folder, in.Image.Levels[level].Path), ".zarray");
    std::vector<char> bytes;
    if (!vtksys::SystemTools::FileExists(path, true))
    {
      return "has no .zarray for " + in.LevelName(level) + " (expected '" + path + "')";
    }
    if (!mcv::zarr::readFile(path, bytes))
    {
      return "cannot read '" + path + "'";
    }
    std::string problem =
      mcv::zarr::parseArrayMeta(std::string(bytes.begin(), bytes.end()), in.Array);
    if (!problem.empty())
    {
      return "has " + in.LevelName(level) + " whose .zarray " + problem;
    }
    const std::size_t axes = in.Image.Axes.size();
    if (in.Array.Shape.size() != axes)
    {
      std::string names;
      for (const auto& a : in.Image.Axes)
      {
        names += (names.empty() ? "" : ", ") + a.Name;
      }
      return "has " + in.LevelName(level) + " of shape " + shapeText(in.Array.Shape) + " (" +
        std::to_string(in.Array.Shape.size()) + " dimensions) for the " +
        std::to_string(axes) + " axes " + names + " of its multiscales";
    }
    for (int a : { in.X, in.Y, in.Z })
    {
      if (a >= 0 && in.Array.Shape[a] > VTK_INT_MAX / 2)
      {
        return "has " + in.LevelName(level) + " of shape " + shapeText(in.Array.Shape) +
          ", too many voxels along one axis for an image";
      }
    }
    return "";
  };
  // Bytes of one time point of the level in in.Array: all channels.
  auto bytesPerTimePoint = [&]() {
    double voxels = 1;
    for (int a : { in.C, in.Z, in.Y, in.X })
    {
      voxels *= a >= 0 ? static_cast<double>(in.Array.Shape[a]) : 1.0;
    }
    return voxels;
  };

  auto readHeader = [&]() -> std::string {
    if (folder.empty())
    {
      return "has no name (set FileName to the image's folder)";
    }
    if (!vtksys::SystemTools::FileIsDirectory(folder))
    {
      return "is not a folder";
    }
    const std::string attrs = joinPath(folder, ".zattrs");
    if (!vtksys::SystemTools::FileExists(attrs, true))
    {
      return vtksys::SystemTools::FileExists(joinPath(folder, ".zarray"), true)
        ? "is a plain Zarr array, not an OME-Zarr image (it has no .zattrs with multiscales)"
        : "has no .zattrs (the OME-Zarr metadata with multiscales)";
    }
    std::vector<char> bytes;
    if (!mcv::zarr::readFile(attrs, bytes))
    {
      return "cannot read '" + attrs + "'";
    }
    std::string problem =
      mcv::zarr::parseImageMeta(std::string(bytes.begin(), bytes.end()), in.Image);
    if (!problem.empty())
    {
      return problem;
    }
    this->NumberOfLevels = static_cast<int>(in.Image.Levels.size());
    in.T = in.Image.AxisIndex("t");
    in.C = in.Image.AxisIndex("c");
    in.Z = in.Image.AxisIndex("z");
    in.Y = in.Image.AxisIndex("y");
    in.X = in.Image.AxisIndex("x");

    if (this->ResolutionLevel >= this->NumberOfLevels)
    {
      return "has no resolution level " + std::to_string(this->ResolutionLevel) + " (it has " +
        std::to_string(this->NumberOfLevels) + ": 0 to " +
        std::to_string(this->NumberOfLevels - 1) + ")";
    }
    if (this->ResolutionLevel < -1)
    {
      return "was asked for resolution level " + std::to_string(this->ResolutionLevel) +
        " (0 is the finest, -1 the finest that fits in memory)";
    }
    if (this->ResolutionLevel >= 0)
    {
      // The memory is checked against the extent each update asks for (RequestData).
      problem = readLevel(this->ResolutionLevel);
      if (!problem.empty())
      {
        return problem;
      }
      in.Level = this->ResolutionLevel;
    }
    else
    {
      // The finest level whose one time point fits in memory.
      std::string tooBig;
      for (int level = 0; level < this->NumberOfLevels && in.Level < 0; ++level)
      {
        problem = readLevel(level);
        if (!problem.empty())
        {
          return problem;
        }
        tooBig = mcv::checkFitsInMemory(bytesPerTimePoint(), in.Array.ItemSize);
        if (tooBig.empty())
        {
          in.Level = level;
        }
      }
      if (in.Level < 0)
      {
        return "has no resolution level that fits in memory: the coarsest, " +
          in.LevelName(this->NumberOfLevels - 1) + ", " + tooBig;
      }
    }

    const mcv::zarr::ArrayMeta& a = in.Array;
    const mcv::zarr::Level& level = in.Image.Levels[in.Level];
    in.Channels = in.C >= 0 ? a.Shape[in.C] : 1;
    const int spatial[3] = { in.X, in.Y, in.Z };
    for (int i = 0; i < 3; ++i)
    {
      const int axis = spatial[i];
      in.Whole[2 * i] = 0;
      in.Whole[2 * i + 1] = axis >= 0 ? static_cast<int>(a.Shape[axis]) - 1 : 0;
      in.Spacing[i] = axis >= 0 ? level.Scale[axis] : 1.0;
      in.Origin[i] = axis >= 0 ? level.Translation[axis] : 0.0;
    }
    problem = mcv::checkSpacing(in.Spacing, 3, "the scale of " + in.LevelName(in.Level));
    if (!problem.empty())
    {
      return problem;
    }
    in.TimeSteps.clear();
    if (in.T >= 0)
    {
      for (std::int64_t t = 0; t < a.Shape[in.T]; ++t)
      {
        in.TimeSteps.push_back(
          level.Translation[in.T] + static_cast<double>(t) * level.Scale[in.T]);
      }
    }
    if (!in.Image.Channels.empty() &&
      static_cast<std::int64_t>(in.Image.Channels.size()) != in.Channels)
    {
      vtkWarningMacro(<< this->Describe() << " names " << in.Image.Channels.size()
                      << " channels in omero but its arrays have " << in.Channels
                      << "; the channels without an omero entry are named C<number>.");
    }
    in.Names = channelNames(in.Image.Channels, in.Channels);
    return "";
  };

  in.Refused =
    !mcv::checkedRequestInformation(this, outputVector, this->Describe(), readHeader);
  if (in.Refused)
  {
    return 0;
  }
  this->LevelRead = in.Level;
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), in.Whole, 6);
  outInfo->Set(vtkDataObject::SPACING(), in.Spacing, 3);
  outInfo->Set(vtkDataObject::ORIGIN(), in.Origin, 3);
  // Any sub-extent is read by itself: ParaView's pieces each read their own chunks.
  outInfo->Set(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT(), 1);
  if (in.TimeSteps.empty())
  {
    outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
    outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  }
  else
  {
    outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_STEPS(), in.TimeSteps.data(),
      static_cast<int>(in.TimeSteps.size()));
    const double range[2] = { std::min(in.TimeSteps.front(), in.TimeSteps.back()),
      std::max(in.TimeSteps.front(), in.TimeSteps.back()) };
    outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
  }
  vtkDataObject::SetPointDataActiveScalarInfo(outInfo, vtkTypeOf(in.Array), 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkOMEZarrReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  Internals& in = *this->Impl;
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  this->BytesRead = 0;
  if (in.Refused || !output)
  {
    if (output)
    {
      output->Initialize();
    }
    return 0;
  }
  auto refuse = [&](const std::string& problem) {
    output->Initialize();
    vtkErrorMacro(<< this->Describe() << " " << problem << ". Nothing is read.");
    return 0;
  };
  const mcv::zarr::ArrayMeta& a = in.Array;
  const std::string levelFolder =
    joinPath(this->FileName ? this->FileName : "", in.Image.Levels[in.Level].Path);

  int ext[6];
  std::copy(in.Whole, in.Whole + 6, ext);
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
  {
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), ext);
  }
  bool empty = false;
  for (int i = 0; i < 3; ++i)
  {
    ext[2 * i] = std::max(ext[2 * i], in.Whole[2 * i]);
    ext[2 * i + 1] = std::min(ext[2 * i + 1], in.Whole[2 * i + 1]);
    empty = empty || ext[2 * i + 1] < ext[2 * i];
  }

  // The time point: the last step at or before the one asked for (the first if earlier).
  std::int64_t timeIndex = 0;
  if (!in.TimeSteps.empty() && outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
  {
    const double t = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
    for (std::size_t i = 0; i < in.TimeSteps.size(); ++i)
    {
      if (in.TimeSteps[i] <= t)
      {
        timeIndex = static_cast<std::int64_t>(i);
      }
    }
  }

  const std::int64_t nx = empty ? 0 : ext[1] - ext[0] + 1;
  const std::int64_t ny = empty ? 0 : ext[3] - ext[2] + 1;
  const std::int64_t nz = empty ? 0 : ext[5] - ext[4] + 1;
  const std::string tooBig = mcv::checkFitsInMemory(
    static_cast<double>(nx) * ny * nz * static_cast<double>(in.Channels), a.ItemSize);
  if (!tooBig.empty())
  {
    return refuse("cannot hold the extent asked of " + in.LevelName(in.Level) + " (" +
      std::to_string(nx) + " x " + std::to_string(ny) + " x " + std::to_string(nz) + ", " +
      std::to_string(in.Channels) + " channels): it " + tooBig);
  }

  const int vtkType = vtkTypeOf(a);
  std::vector<vtkSmartPointer<vtkDataArray>> arrays;
  for (std::int64_t c = 0; c < in.Channels; ++c)
  {
    vtkSmartPointer<vtkDataArray> array =
      vtkSmartPointer<vtkDataArray>::Take(vtkDataArray::CreateDataArray(vtkType));
    array->SetName(in.Names[c].c_str());
    array->SetNumberOfTuples(nx * ny * nz);
    array->Fill(a.FillValue); // what the chunks absent from the folder hold
    arrays.push_back(array);
  }

  // The range of element indices asked along each axis of the array, and of chunk indices.
  const std::size_t rank = a.Shape.size();
  std::vector<std::int64_t> lo(rank, 0), hi(rank, 0);
  auto setRange = [&](int axis, std::int64_t first, std::int64_t last) {
    if (axis >= 0)
    {
      lo[axis] = first;
      hi[axis] = last;
    }
  };
  setRange(in.T, timeIndex, timeIndex);
  setRange(in.C, 0, in.Channels - 1);
  setRange(in.Z, ext[4], ext[5]);
  setRange(in.Y, ext[2], ext[3]);
  setRange(in.X, ext[0], ext[1]);
  std::vector<std::int64_t> first(rank), last(rank), chunk(rank);
  std::int64_t chunkCount = 1;
  for (std::size_t i = 0; i < rank; ++i)
  {
    first[i] = lo[i] / a.Chunks[i];
    last[i] = hi[i] / a.Chunks[i];
    chunkCount *= last[i] - first[i] + 1;
  }
  // Element strides inside a chunk (C order: last axis fastest; F order: first axis).
  std::vector<std::int64_t> stride(rank, 1);
  if (a.FortranOrder)
  {
    for (std::size_t i = 1; i < rank; ++i)
    {
      stride[i] = stride[i - 1] * a.Chunks[i - 1];
    }
  }
  else
  {
    for (std::size_t i = rank - 1; i-- > 0;)
    {
      stride[i] = stride[i + 1] * a.Chunks[i + 1];
    }
  }
  auto strideOf = [&](int axis) { return axis >= 0 ? stride[axis] : 0; };
  const std::int64_t sc = strideOf(in.C), sz = strideOf(in.Z), sy = strideOf(in.Y),
                     sx = strideOf(in.X);
  const bool swap = a.ItemSize > 1 && a.BigEndian == mcv::zarr::hostIsLittleEndian();
  const int item = a.ItemSize;

  std::vector<char> stored, decoded;
  std::int64_t done = 0;
  chunk = first;
  for (bool more = !empty; more;)
  {
    const std::string key = mcv::zarr::chunkKey(chunk, a.Separator);
    const std::string file = joinPath(levelFolder, key);
    if (vtksys::SystemTools::FileExists(file, true))
    {
      if (!mcv::zarr::readFile(file, stored))
      {
        return refuse("cannot read chunk '" + file + "'");
      }
      this->BytesRead += static_cast<vtkTypeInt64>(stored.size());
      const std::string problem = mcv::zarr::decodeChunk(a, stored, decoded);
      if (!problem.empty())
      {
        return refuse("has " + in.LevelName(in.Level) + " whose chunk '" + key + "' " + problem);
      }
      if (swap)
      {
        mcv::zarr::swapBytes(decoded.data(), a.ChunkElements(), item);
      }
      // The part of the chunk inside the extent asked, per axis (whole-array indices).
      auto overlap = [&](int axis, std::int64_t& from, std::int64_t& to) {
        if (axis < 0)
        {
          from = to = 0;
          return;
        }
        const std::int64_t c0 = chunk[axis] * a.Chunks[axis];
        from = std::max(lo[axis], c0);
        to = std::min({ hi[axis], c0 + a.Chunks[axis] - 1, a.Shape[axis] - 1 });
      };
      auto base = [&](int axis) { return axis >= 0 ? chunk[axis] * a.Chunks[axis] : 0; };
      std::int64_t c0, c1, z0, z1, y0, y1, x0, x1;
      overlap(in.C, c0, c1);
      overlap(in.Z, z0, z1);
      overlap(in.Y, y0, y1);
      overlap(in.X, x0, x1);
      std::int64_t offset = 0; // the chunk's element of the fixed axes (t)
      if (in.T >= 0)
      {
        offset += (timeIndex - base(in.T)) * stride[in.T];
      }
      const std::int64_t run = x1 - x0 + 1;
      for (std::int64_t c = c0; c <= c1; ++c)
      {
        char* dst = static_cast<char*>(arrays[c]->GetVoidPointer(0));
        for (std::int64_t z = z0; z <= z1; ++z)
        {
          for (std::int64_t y = y0; y <= y1; ++y)
          {
            const std::int64_t src = offset + (c - base(in.C)) * sc + (z - base(in.Z)) * sz +
              (y - base(in.Y)) * sy + (x0 - base(in.X)) * sx;
            const std::int64_t out = ((z - ext[4]) * ny + (y - ext[2])) * nx + (x0 - ext[0]);
            if (sx == 1)
            {
              std::memcpy(dst + out * item, decoded.data() + src * item, run * item);
            }
            else
            {
              for (std::int64_t x = 0; x < run; ++x)
              {
                std::memcpy(dst + (out + x) * item, decoded.data() + (src + x * sx) * item, item);
              }
            }
          }
        }
      }
    }
    this->UpdateProgress(static_cast<double>(++done) / static_cast<double>(chunkCount));
    // The next chunk index (the last axis fastest).
    more = false;
    for (std::size_t i = rank; i-- > 0;)
    {
      if (++chunk[i] <= last[i])
      {
        more = true;
        break;
      }
      chunk[i] = first[i];
    }
  }

  if (empty)
  {
    output->SetExtent(0, -1, 0, -1, 0, -1);
  }
  else
  {
    output->SetExtent(ext);
  }
  output->SetSpacing(in.Spacing);
  output->SetOrigin(in.Origin);
  for (std::int64_t c = 0; c < in.Channels; ++c)
  {
    output->GetPointData()->AddArray(arrays[c]);
  }
  if (!arrays.empty())
  {
    output->GetPointData()->SetActiveScalars(arrays[0]->GetName());
  }
  if (!in.TimeSteps.empty())
  {
    output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), in.TimeSteps[timeIndex]);
  }

  // What the file says besides the voxels, for the Information panel and the tools.
  vtkFieldData* fields = output->GetFieldData();
  auto addString = [&](const char* name, const std::vector<std::string>& values) {
    vtkNew<vtkStringArray> s;
    s->SetName(name);
    for (const std::string& v : values)
    {
      s->InsertNextValue(v);
    }
    fields->AddArray(s);
  };
  std::string lengthUnit, timeUnit;
  for (int axis : { in.X, in.Y, in.Z })
  {
    if (axis >= 0 && lengthUnit.empty())
    {
      lengthUnit = in.Image.Axes[axis].Unit;
    }
  }
  if (in.T >= 0)
  {
    timeUnit = in.Image.Axes[in.T].Unit;
  }
  addString("LengthUnit", { lengthUnit });
  addString("TimeUnit", { timeUnit });
  std::vector<std::string> colors;
  for (std::int64_t c = 0; c < in.Channels; ++c)
  {
    colors.push_back(
      c < static_cast<std::int64_t>(in.Image.Channels.size()) ? in.Image.Channels[c].Color : "");
  }
  addString("ChannelColors", colors);
  vtkNew<vtkIntArray> level;
  level->SetName("ResolutionLevel");
  level->InsertNextValue(in.Level);
  fields->AddArray(level);
  vtkNew<vtkTypeInt64Array> bytes;
  bytes->SetName("BytesRead");
  bytes->InsertNextValue(this->BytesRead);
  fields->AddArray(bytes);
  return 1;
}

//------------------------------------------------------------------------------
void vtkOMEZarrReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ResolutionLevel: " << this->ResolutionLevel << "\n";
  os << indent << "LevelRead: " << this->LevelRead << "\n";
  os << indent << "NumberOfLevels: " << this->NumberOfLevels << "\n";
  os << indent << "BytesRead: " << this->BytesRead << "\n";
}

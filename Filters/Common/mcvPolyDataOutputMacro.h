/**
 * The polydata output of the filters that derive from an image algorithm (through
 * vtkGaussianWidgetsAlgorithm) but produce polydata: BestViewpoint (the interest points and
 * the view) and ReducedDomain (the reduced domain's points). mcvPolyDataOutputMacro(), in a
 * public section, declares GetOutput() and GetOutput(port) returning the polydata (the
 * base's would cast the output to image data and return null) and, protected,
 * FillOutputPortInformation saying that every output port holds vtkPolyData: the two
 * halves of "the output is polydata" in one place. The section after it is public again.
 */
#ifndef mcvPolyDataOutputMacro_h
#define mcvPolyDataOutputMacro_h

#include <vtkDataObject.h>
#include <vtkInformation.h>
#include <vtkPolyData.h>

#define mcvPolyDataOutputMacro()                                                               \
protected:                                                                                     \
  int FillOutputPortInformation(int, vtkInformation* info) override                            \
  {                                                                                            \
    info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkPolyData");                                 \
    return 1;                                                                                  \
  }                                                                                            \
                                                                                               \
public:                                                                                        \
  vtkPolyData* GetOutput(int port)                                                             \
  {                                                                                            \
    return vtkPolyData::SafeDownCast(this->GetOutputDataObject(port));                         \
  }                                                                                            \
  vtkPolyData* GetOutput() { return this->GetOutput(0); }

#endif

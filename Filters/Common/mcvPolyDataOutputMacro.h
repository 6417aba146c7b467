/**
 * GetOutput for the filters that derive from an image algorithm (through
 * vtkGaussianWidgetsAlgorithm) but produce polydata: BestViewpoint (the interest points and
 * the view) and ReducedDomain (the reduced domain's points). The base's GetOutput would cast
 * the output to image data and return null; mcvPolyDataOutputMacro(), in a public section,
 * declares GetOutput() and GetOutput(port) returning the polydata. The class still says in
 * FillOutputPortInformation that its output is vtkPolyData.
 */
#ifndef mcvPolyDataOutputMacro_h
#define mcvPolyDataOutputMacro_h

#include <vtkPolyData.h>

#define mcvPolyDataOutputMacro()                                                               \
  vtkPolyData* GetOutput() { return this->GetOutput(0); }                                      \
  vtkPolyData* GetOutput(int port)                                                             \
  {                                                                                            \
    return vtkPolyData::SafeDownCast(this->GetOutputDataObject(port));                         \
  }

#endif

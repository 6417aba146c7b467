/**
 * mcvEnumPropertyMacro(name, first, last) declares an int property whose values are the
 * enumerators first..last of an enum of the class: SetName clamps to [first, last] (a value
 * outside is not an error, as vtkSetClampMacro) and GetName returns it. The filters declare
 * every such choice property (Device, Normalization, FeatureSet, Method, OpacitySource,
 * CoordinatePrecision) this way, once, instead of a vtkSetClampMacro/vtkGetMacro pair each.
 * In a public section, where ParaView's client-server wrapper (which expands it) makes
 * both methods callable from the ServerManager XML and the Python proxies.
 */
#ifndef mcvEnumPropertyMacro_h
#define mcvEnumPropertyMacro_h

#include "vtkSetGet.h" // for vtkSetClampMacro, vtkGetMacro

#define mcvEnumPropertyMacro(name, first, last)                                                \
  vtkSetClampMacro(name, int, first, last);                                                    \
  vtkGetMacro(name, int)

#endif

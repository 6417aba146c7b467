/**
 * The `GaussianWidgets` property, declared once for every class that offers it: the
 * "Gaussian TF Volume" representation and vtkGaussianWidgetsAlgorithm (the base of
 * BestViewpoint and ReducedDomain). mcvGaussianWidgetValuesMacro() declares, in a public
 * section, the four methods through which ParaView sets a variable-length double property
 * element by element (set_number_command + use_index):
 *
 * - SetNumberOfGaussianWidgetValues(count) and SetGaussianWidgetValue(index, value) set the
 *   flat list, 8 values per widget: cx, cy, cz, sigma, r, g, b, opacity,
 * - GetNumberOfGaussianWidgetValues() and GetGaussianWidgetValue(index) read it back
 *   (0 for an index outside the list).
 *
 * Each class keeps the list in an mcv::vtkhelpers::WidgetValues (mcvWidgetValues.h) and
 * says in its own .cxx what a change marks modified. The list is checked where it is used
 * (mcv::parseGaussianWidgets), not when it is set.
 */
#ifndef mcvGaussianWidgetValuesMacro_h
#define mcvGaussianWidgetValuesMacro_h

#define mcvGaussianWidgetValuesMacro()                                                         \
  void SetNumberOfGaussianWidgetValues(int count);                                             \
  void SetGaussianWidgetValue(int index, double value);                                        \
  int GetNumberOfGaussianWidgetValues();                                                       \
  double GetGaussianWidgetValue(int index)

#endif

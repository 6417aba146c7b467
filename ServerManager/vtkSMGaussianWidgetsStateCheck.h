/**
 * @class vtkSMGaussianWidgetsStateCheck
 * @brief Checks the Gaussian widgets of every state file ParaView loads.
 *
 * ParaView's state loader parses each property element with C++ streams, so a "nan" or
 * "inf" in a state file (written by hand, by a script, by another tool) loads as 0.0: a
 * widget moves to the origin or vanishes without a word, whether the file is loaded with
 * File > Load State, paraview.simple.LoadState or pvpython's LoadState. Once the plugin is
 * loaded, this class watches the proxy manager: after each state is loaded
 * (vtkCommand::LoadStateEvent, which carries the XML as it was in the file) every value of
 * every GaussianWidgets property is read again as text, and a value that is not a finite
 * number, a centre beyond 1e30 or a sigma beyond 1e30 is an error naming the proxy, the
 * widget and the field (the limits of multichannel_explorer.check_widget_values without
 * the domain's size, which the file does not hold).
 */
#pragma once

#include "mcvServerManagerDomainsModule.h" // for export macro
#include "vtkObject.h"

#include <string> // for std::string
#include <vector> // for std::vector

class vtkPVXMLElement;

class MCVSERVERMANAGERDOMAINS_EXPORT vtkSMGaussianWidgetsStateCheck : public vtkObject
{
public:
  static vtkSMGaussianWidgetsStateCheck* New();
  vtkTypeMacro(vtkSMGaussianWidgetsStateCheck, vtkObject);

#ifndef __VTK_WRAP__
  /** The problems of a state's XML, one line each (empty: none). */
  static std::vector<std::string> Check(vtkPVXMLElement* root);
#endif

  /**
   * Watches the proxy manager's loaded states (once per process; the plugin's library
   * calls it when it is loaded). False when there is no proxy manager yet.
   */
  static bool Install();

protected:
  vtkSMGaussianWidgetsStateCheck() = default;
  ~vtkSMGaussianWidgetsStateCheck() override = default;

private:
  vtkSMGaussianWidgetsStateCheck(const vtkSMGaussianWidgetsStateCheck&) = delete;
  void operator=(const vtkSMGaussianWidgetsStateCheck&) = delete;
};

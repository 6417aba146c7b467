/**
 * @class   vtkGaussianWidgetsAlgorithm
 * @brief   base of the filters that take the Gaussian widgets of the transfer function.
 *
 * BestViewpoint (its widget opacity) and ReducedDomain (the widgets' colours on the domain
 * cloud) read the same flat widget list as the "Gaussian TF Volume" representation's
 * `GaussianWidgets` property: 8 values per widget (cx, cy, cz, sigma, r, g, b, opacity).
 * ParaView sets a variable-length double property element by element
 * (set_number_command + use_index); the four methods doing so are defined here once
 * (declared by mcvGaussianWidgetValuesMacro.h, as the representation's are).
 */

#ifndef vtkGaussianWidgetsAlgorithm_h
#define vtkGaussianWidgetsAlgorithm_h

#include "mcvFiltersCommonModule.h"       // for export macro
#include "mcvGaussianWidgetValuesMacro.h" // for mcvGaussianWidgetValuesMacro
#include "vtkMultichannelAlgorithm.h"

#include <memory> // for std::unique_ptr

#ifndef __VTK_WRAP__
namespace mcv
{
struct WidgetList;
}
#endif

class MCVFILTERSCOMMON_EXPORT vtkGaussianWidgetsAlgorithm : public vtkMultichannelAlgorithm
{
public:
  vtkTypeMacro(vtkGaussianWidgetsAlgorithm, vtkMultichannelAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /** The `GaussianWidgets` property (mcvGaussianWidgetValuesMacro.h); a change is Modified(). */
  mcvGaussianWidgetValuesMacro();

protected:
  vtkGaussianWidgetsAlgorithm();
  ~vtkGaussianWidgetsAlgorithm() override;

#ifndef __VTK_WRAP__
  // The list parsed by the core (mcv::parseGaussianWidgets: its error says what is wrong).
  mcv::WidgetList ParseGaussianWidgets() const;
#endif

private:
  vtkGaussianWidgetsAlgorithm(const vtkGaussianWidgetsAlgorithm&) = delete;
  void operator=(const vtkGaussianWidgetsAlgorithm&) = delete;

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif

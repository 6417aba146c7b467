/**
 * @class   vtkSMChannelArrayListDomain
 * @brief   the input's point arrays a filter of the suite may take as channels
 *
 * An ArrayListDomain (XML element ChannelArrayListDomain, the same attributes and required
 * properties) that leaves out VTK's bookkeeping arrays, vtkGhostType and ResampleToImage's
 * vtkValidPointMask, and the suite's outputs, Features, Foreground, ReducedCoordinates and
 * HarrisScore, VoxelIndex (mcvInternalArrays.h). The filters never take those as channels by default,
 * but the plain domain listed them and, as a repeatable property's default is every array
 * of the domain, showed them checked in the Channels list.
 */
#ifndef vtkSMChannelArrayListDomain_h
#define vtkSMChannelArrayListDomain_h

#include "mcvServerManagerDomainsModule.h" // export macro
#include "vtkSMArrayListDomain.h"

#include <string> // for std::string
#include <vector> // for std::vector

class MCVSERVERMANAGERDOMAINS_EXPORT vtkSMChannelArrayListDomain : public vtkSMArrayListDomain
{
public:
  static vtkSMChannelArrayListDomain* New();
  vtkTypeMacro(vtkSMChannelArrayListDomain, vtkSMArrayListDomain);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * The superclass's update; then, when the property holds no channel, or still holds the
   * channels this domain gave it and nobody changed them since, the property gets every
   * channel of the current input (none while the input has not run: the filters read an
   * empty list as every channel). A filter made from Python before its input ran had an
   * empty Channels property, used as "every channel", while the GUI's Channels list,
   * filled once the input ran, showed every channel unchecked; and paraview.simple
   * connects a new filter to the active source before its Input, so the channels given
   * then must follow the input set afterwards.
   */
  void Update(vtkSMProperty* requestingProperty) override;

protected:
  vtkSMChannelArrayListDomain();
  ~vtkSMChannelArrayListDomain() override;

  bool IsFilteredArray(vtkPVDataInformation* info, int association, const char* arrayName) override;

private:
  vtkSMChannelArrayListDomain(const vtkSMChannelArrayListDomain&) = delete;

  // The channels this domain last gave the property (Filled: it did).
  std::vector<std::string> FilledValues;
  bool Filled = false;
  void operator=(const vtkSMChannelArrayListDomain&) = delete;
};

#endif

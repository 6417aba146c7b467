/**
 * @class   vtkSMChannelArrayListDomain
 * @brief   the input's point arrays a filter of the suite may take as channels
 *
 * An ArrayListDomain (XML element ChannelArrayListDomain, the same attributes and required
 * properties) that leaves out VTK's bookkeeping arrays, vtkGhostType and ResampleToImage's
 * vtkValidPointMask, and the suite's outputs, Features, Foreground, ReducedCoordinates and
 * HarrisScore (mcvInternalArrays.h). The filters never take those as channels by default,
 * but the plain domain listed them and, as a repeatable property's default is every array
 * of the domain, showed them checked in the Channels list.
 */
#ifndef vtkSMChannelArrayListDomain_h
#define vtkSMChannelArrayListDomain_h

#include "mcvServerManagerDomainsModule.h" // export macro
#include "vtkSMArrayListDomain.h"

class MCVSERVERMANAGERDOMAINS_EXPORT vtkSMChannelArrayListDomain : public vtkSMArrayListDomain
{
public:
  static vtkSMChannelArrayListDomain* New();
  vtkTypeMacro(vtkSMChannelArrayListDomain, vtkSMArrayListDomain);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * The superclass's update; and when the list of channels was empty before (the input had
   * not run yet) and the property holds no channel, the property gets the domain's default,
   * every channel. A filter made from Python before its input ran had an empty Channels
   * property, which the filters read as "every channel", while the GUI's Channels list,
   * filled once the input ran, showed every channel unchecked: now it shows what is used.
   */
  void Update(vtkSMProperty* requestingProperty) override;

protected:
  vtkSMChannelArrayListDomain();
  ~vtkSMChannelArrayListDomain() override;

  bool IsFilteredArray(vtkPVDataInformation* info, int association, const char* arrayName) override;

private:
  vtkSMChannelArrayListDomain(const vtkSMChannelArrayListDomain&) = delete;
  void operator=(const vtkSMChannelArrayListDomain&) = delete;
};

#endif

#include "vtkSMGaussianWidgetsStateCheck.h"

#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkObjectFactory.h"
#include "vtkPVXMLElement.h"
#include "vtkSMProxyManager.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

vtkStandardNewMacro(vtkSMGaussianWidgetsStateCheck);

namespace
{
const char* const kFields[8] = { "cx", "cy", "cz", "sigma", "r", "g", "b", "opacity" };
constexpr double kAbsurd = 1e30;

// The number a state file's text stands for; false when it is none (or not finite).
bool finiteNumber(const char* text, double& value)
{
  if (!text || !*text)
  {
    return false;
  }
  char* end = nullptr;
  errno = 0;
  value = std::strtod(text, &end);
  while (end && (*end == ' ' || *end == '\t'))
  {
    ++end;
  }
  return end && *end == '\0' && std::isfinite(value);
}

// The problems of one GaussianWidgets property element of proxy `where`.
void checkProperty(vtkPVXMLElement* property, const std::string& where, std::vector<std::string>& problems)
{
  for (unsigned int e = 0; e < property->GetNumberOfNestedElements(); ++e)
  {
    vtkPVXMLElement* element = property->GetNestedElement(e);
    if (!element->GetName() || std::string(element->GetName()) != "Element")
    {
      continue;
    }
    int index = 0;
    element->GetScalarAttribute("index", &index);
    const char* text = element->GetAttribute("value");
    const int widget = index / 8, field = index % 8;
    const std::string name = kFields[field];
    double value = 0;
    std::ostringstream os;
    if (!finiteNumber(text, value))
    {
      os << where << ": widget " << widget << "'s " << name << " is '" << (text ? text : "")
         << "', not a finite number (ParaView loaded it as 0)";
    }
    else if (field < 3 && std::abs(value) > kAbsurd)
    {
      os << where << ": widget " << widget << "'s centre " << name << " = " << value << " lies beyond " << kAbsurd;
    }
    else if (field == 3 && value > kAbsurd)
    {
      os << where << ": widget " << widget << "'s sigma = " << value << " exceeds " << kAbsurd
         << " (no widget is that wide)";
    }
    if (!os.str().empty())
    {
      problems.push_back(os.str());
    }
  }
}

void collect(vtkPVXMLElement* element, std::vector<std::string>& problems)
{
  if (!element)
  {
    return;
  }
  const char* name = element->GetName();
  if (name && std::string(name) == "Proxy")
  {
    for (unsigned int p = 0; p < element->GetNumberOfNestedElements(); ++p)
    {
      vtkPVXMLElement* property = element->GetNestedElement(p);
      const char* propertyName = property->GetAttribute("name");
      if (property->GetName() && std::string(property->GetName()) == "Property" && propertyName &&
        std::string(propertyName) == "GaussianWidgets")
      {
        std::ostringstream where;
        where << "State file: GaussianWidgets of " << (element->GetAttribute("type") ? element->GetAttribute("type") : "?")
              << " proxy " << (element->GetAttribute("id") ? element->GetAttribute("id") : "?");
        checkProperty(property, where.str(), problems);
      }
    }
    return;
  }
  for (unsigned int c = 0; c < element->GetNumberOfNestedElements(); ++c)
  {
    collect(element->GetNestedElement(c), problems);
  }
}

void onLoadState(vtkObject* caller, unsigned long, void*, void* callData)
{
  const auto* info = static_cast<const vtkSMProxyManager::LoadStateInformation*>(callData);
  if (!info)
  {
    return;
  }
  for (const std::string& problem : vtkSMGaussianWidgetsStateCheck::Check(info->RootElement))
  {
    vtkErrorWithObjectMacro(caller, << problem);
  }
}

// The plugin's library watches loaded states from the moment it is loaded.
struct InstallWhenLoaded
{
  InstallWhenLoaded() { vtkSMGaussianWidgetsStateCheck::Install(); }
} installWhenLoaded;
} // namespace

//------------------------------------------------------------------------------
std::vector<std::string> vtkSMGaussianWidgetsStateCheck::Check(vtkPVXMLElement* root)
{
  std::vector<std::string> problems;
  collect(root, problems);
  return problems;
}

//------------------------------------------------------------------------------
bool vtkSMGaussianWidgetsStateCheck::Install()
{
  static bool installed = false;
  if (installed)
  {
    return true;
  }
  if (!vtkSMProxyManager::IsInitialized())
  {
    return false;
  }
  vtkNew<vtkCallbackCommand> command;
  command->SetCallback(onLoadState);
  vtkSMProxyManager::GetProxyManager()->AddObserver(vtkCommand::LoadStateEvent, command);
  installed = true;
  return true;
}

#include "pqFeatureCountWidget.h"

#include "pqApplicationCore.h"
#include "pqPipelineSource.h"
#include "pqServerManagerModel.h"
#include "vtkCommand.h"
#include "vtkEventQtSlotConnect.h"
#include "vtkPVArrayInformation.h"
#include "vtkPVDataInformation.h"
#include "vtkPVDataSetAttributesInformation.h"
#include "vtkSMProperty.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMSourceProxy.h"
#include "vtkType.h"

#include <QLabel>
#include <QStringList>

#include <cstring>
#include <string>
#include <utility>

namespace
{
const char* const WatchedProperties[] = { "Channels", "FeatureSet", "Intensity", "Gradient",
  "GradientMagnitude", "Laplacian", "LocalMean", "LocalVariance", "Features" };

// Arrays never taken as channels: ParaView's bookkeeping arrays and the suite's outputs.
bool isNotAChannel(const char* name)
{
  static const char* const names[] = { "vtkGhostType", "vtkValidPointMask", "Features",
    "Foreground", "ReducedCoordinates", "HarrisScore", "VoxelIndex" };
  for (const char* n : names)
  {
    if (name && std::strcmp(name, n) == 0)
    {
      return true;
    }
  }
  return false;
}

int intValue(vtkSMProxy* proxy, const char* name, int fallback)
{
  vtkSMProperty* property = proxy->GetProperty(name);
  return property ? vtkSMPropertyHelper(property).GetAsInt() : fallback;
}

vtkSMSourceProxy* inputOf(vtkSMProxy* proxy, unsigned int* port = nullptr)
{
  vtkSMProperty* input = proxy->GetProperty("Input");
  if (!input || vtkSMPropertyHelper(input).GetNumberOfElements() == 0)
  {
    return nullptr;
  }
  if (port)
  {
    *port = vtkSMPropertyHelper(input).GetOutputPort(0);
  }
  return vtkSMSourceProxy::SafeDownCast(vtkSMPropertyHelper(input).GetAsProxy());
}
} // namespace

//-----------------------------------------------------------------------------
pqFeatureCountWidget::pqFeatureCountWidget(
  vtkSMProxy* smproxy, vtkSMProperty* smproperty, QWidget* parentWidget)
  : Superclass(smproxy, smproperty, parentWidget, "FeatureCount", false)
{
  this->Label = this->addMessageLabel("featureCount");

  // Unchecked edits (before Apply) are shown too.
  for (const char* name : WatchedProperties)
  {
    if (vtkSMProperty* property = smproxy->GetProperty(name))
    {
      this->Connections->Connect(property, vtkCommand::UncheckedPropertyModifiedEvent, this,
        SLOT(updateCount()), nullptr, 0.0, Qt::QueuedConnection);
      this->Connections->Connect(property, vtkCommand::ModifiedEvent, this,
        SLOT(updateCount()), nullptr, 0.0, Qt::QueuedConnection);
    }
  }
  if (vtkSMProperty* input = smproxy->GetProperty("Input"))
  {
    this->Connections->Connect(input, vtkCommand::ModifiedEvent, this, SLOT(watchInput()));
  }
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  if (pqPipelineSource* self = model->findItem<pqPipelineSource*>(smproxy))
  {
    QObject::connect(
      self, SIGNAL(dataUpdated(pqPipelineSource*)), this, SLOT(updateCount()));
  }
  this->watchInput();
}

//-----------------------------------------------------------------------------
pqFeatureCountWidget::~pqFeatureCountWidget() = default;

//-----------------------------------------------------------------------------
void pqFeatureCountWidget::watchInput()
{
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  if (pqPipelineSource* input = model->findItem<pqPipelineSource*>(inputOf(this->proxy())))
  {
    QObject::connect(input, SIGNAL(dataUpdated(pqPipelineSource*)), this, SLOT(updateCount()),
      Qt::UniqueConnection);
  }
  this->updateCount();
}

//-----------------------------------------------------------------------------
void pqFeatureCountWidget::updateCount()
{
  this->Label->setText(this->text());
}

//-----------------------------------------------------------------------------
QString pqFeatureCountWidget::text() const
{
  vtkSMProxy* proxy = this->proxy();
  unsigned int port = 0;
  vtkSMSourceProxy* input = inputOf(proxy, &port);
  vtkPVDataInformation* info = input ? input->GetDataInformation(port) : nullptr;
  vtkPVDataSetAttributesInformation* points = info ? info->GetPointDataInformation() : nullptr;
  if (!points || points->GetNumberOfArrays() == 0)
  {
    return tr("Features: shown once the input has point arrays (Apply the input first).");
  }
  const int featureSet = intValue(proxy, "FeatureSet", 0);
  // DimensionReduction: 3 "Use input array", 4 "Automatic" (the Features array if any).
  if (featureSet == 3 || featureSet == 4)
  {
    std::string name = "Features";
    if (featureSet == 3 && proxy->GetProperty("Features"))
    {
      vtkSMPropertyHelper helper(proxy->GetProperty("Features"));
      helper.SetUseUnchecked(true);
      // SetInputArrayToProcess's 5 elements: idx, port, connection, association, name.
      const char* chosen = helper.GetNumberOfElements() >= 5 ? helper.GetAsString(4) : nullptr;
      name = chosen && *chosen ? chosen : name;
    }
    if (vtkPVArrayInformation* array = points->GetArrayInformation(name.c_str()))
    {
      return tr("<b>%1 features</b>: the components of the input's array '%2'.")
        .arg(array->GetNumberOfComponents())
        .arg(QString::fromStdString(name));
    }
    if (featureSet == 3)
    {
      return tr("No array '%1' in the input.").arg(QString::fromStdString(name));
    }
  }

  // Channels: every component of every selected array; none selected: every numeric array.
  int channels = 0;
  int arrays = 0;
  vtkSMPropertyHelper selected(proxy->GetProperty("Channels"));
  selected.SetUseUnchecked(true);
  for (unsigned int i = 0; i < selected.GetNumberOfElements(); ++i)
  {
    const char* name = selected.GetAsString(i);
    vtkPVArrayInformation* array =
      name && !isNotAChannel(name) ? points->GetArrayInformation(name) : nullptr;
    if (array)
    {
      channels += array->GetNumberOfComponents();
      ++arrays;
    }
  }
  if (arrays == 0)
  {
    for (int i = 0; i < points->GetNumberOfArrays(); ++i)
    {
      vtkPVArrayInformation* array = points->GetArrayInformation(i);
      if (!isNotAChannel(array->GetName()) && array->GetDataType() != VTK_STRING &&
        array->GetDataType() != VTK_BIT)
      {
        channels += array->GetNumberOfComponents();
      }
    }
  }

  int perChannel = 0;
  QString which;
  if (featureSet == 0)
  {
    perChannel = 2;
    which = tr("intensity, gradient magnitude");
  }
  else if (featureSet == 2)
  {
    QStringList ticked;
    const std::pair<const char*, QString> toggles[] = { { "Intensity", tr("intensity") },
      { "Gradient", tr("gradient x, y, z") }, { "GradientMagnitude", tr("gradient magnitude") },
      { "Laplacian", tr("Laplacian") }, { "LocalMean", tr("local mean") },
      { "LocalVariance", tr("local variance") } };
    for (const auto& toggle : toggles)
    {
      vtkSMProperty* property = proxy->GetProperty(toggle.first);
      if (!property)
      {
        continue;
      }
      vtkSMPropertyHelper helper(property);
      helper.SetUseUnchecked(true);
      if (helper.GetAsInt())
      {
        perChannel += std::strcmp(toggle.first, "Gradient") == 0 ? 3 : 1;
        ticked << toggle.second;
      }
    }
    which = ticked.join(", ");
  }
  else
  {
    perChannel = 8;
    which = tr("all eight");
  }
  QString line = tr("<b>%1 features</b>: %2 channel%3 x %4 per channel (%5)")
                   .arg(channels * perChannel)
                   .arg(channels)
                   .arg(channels == 1 ? "" : "s")
                   .arg(perChannel)
                   .arg(which);
  if (perChannel == 0)
  {
    line = tr("<b>No feature selected</b>: tick at least one feature below.");
  }
  else if (channels == 1)
  {
    line += tr(". One channel only: merge the files of several channels with Merge Channels, "
               "or open a multichannel file.");
  }
  return line;
}

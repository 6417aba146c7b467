#include "pqGaussianWidgetHandlesBehavior.h"

#include "pqGaussianWidgetHandles.h"

#include "pqApplicationCore.h"
#include "pqCoreUtilities.h"
#include "pqDataRepresentation.h"
#include "pqOutputPort.h"
#include "pqPipelineFilter.h"
#include "pqRenderView.h"
#include "pqServerManagerModel.h"
#include "vtkCommand.h"
#include "vtkSMProperty.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMProxy.h"

#include <algorithm>
#include <cstring>
#include <utility>

namespace
{
const char* const GaussianTFType = "Gaussian TF Volume";

// A visible "Gaussian TF Volume" display (one that has widgets to drag).
bool isGaussianTFDisplay(pqDataRepresentation* display)
{
  vtkSMProxy* proxy = display ? display->getProxy() : nullptr;
  if (!proxy || !display->isVisible() || !proxy->GetProperty("GaussianWidgets") ||
    !proxy->GetProperty("Representation"))
  {
    return false;
  }
  const char* type = vtkSMPropertyHelper(proxy, "Representation").GetAsString();
  return type && std::strcmp(type, GaussianTFType) == 0;
}
}

//-----------------------------------------------------------------------------
pqGaussianWidgetHandlesBehavior::pqGaussianWidgetHandlesBehavior(QObject* parentObject)
  : Superclass(parentObject)
{
  // Many changes come in bursts (a Show, a layout split): one update after them.
  this->UpdateTimer.setSingleShot(true);
  this->UpdateTimer.setInterval(0);
  QObject::connect(&this->UpdateTimer, &QTimer::timeout, this,
    &pqGaussianWidgetHandlesBehavior::updateHandles);
}

//-----------------------------------------------------------------------------
pqGaussianWidgetHandlesBehavior::~pqGaussianWidgetHandlesBehavior()
{
  this->shutdown();
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetHandlesBehavior::startup()
{
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  QObject::connect(model, &pqServerManagerModel::representationAdded, this,
    &pqGaussianWidgetHandlesBehavior::watch);
  QObject::connect(model, &pqServerManagerModel::representationRemoved, this,
    &pqGaussianWidgetHandlesBehavior::scheduleUpdate);
  // A closing view takes its handles at once, while its interactor is still there.
  QObject::connect(model, &pqServerManagerModel::preViewRemoved, this, [this](pqView* view) {
    for (auto& handles : this->Handles)
    {
      if (handles && handles->domainView() == view)
      {
        delete handles;
      }
    }
  });
  QObject::connect(model, &pqServerManagerModel::sourceRemoved, this,
    &pqGaussianWidgetHandlesBehavior::scheduleUpdate);
  QObject::connect(model,
    QOverload<pqPipelineSource*, pqPipelineSource*, int>::of(
      &pqServerManagerModel::connectionAdded),
    this, &pqGaussianWidgetHandlesBehavior::scheduleUpdate);
  QObject::connect(model,
    QOverload<pqPipelineSource*, pqPipelineSource*, int>::of(
      &pqServerManagerModel::connectionRemoved),
    this, &pqGaussianWidgetHandlesBehavior::scheduleUpdate);
  for (pqDataRepresentation* rep : model->findItems<pqDataRepresentation*>())
  {
    this->watch(rep);
  }
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetHandlesBehavior::shutdown()
{
  this->UpdateTimer.stop();
  for (auto& handles : this->Handles)
  {
    delete handles;
  }
  this->Handles.clear();
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetHandlesBehavior::watch(pqProxy* item)
{
  auto* rep = qobject_cast<pqRepresentation*>(item);
  if (!rep)
  {
    return;
  }
  QObject::connect(rep, &pqRepresentation::visibilityChanged, this,
    &pqGaussianWidgetHandlesBehavior::scheduleUpdate);
  // Switching to or from "Gaussian TF Volume" makes or breaks a pair.
  if (vtkSMProperty* type = rep->getProxy()->GetProperty("Representation"))
  {
    pqCoreUtilities::connect(type, vtkCommand::ModifiedEvent, this, SLOT(scheduleUpdate()));
  }
  this->scheduleUpdate();
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetHandlesBehavior::updateHandles()
{
  // The pairs (domain view, volume display) the pipeline asks for now.
  std::vector<std::pair<pqRenderView*, pqDataRepresentation*>> wanted;
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  for (pqRenderView* view : model->findItems<pqRenderView*>())
  {
    for (pqRepresentation* item : view->getRepresentations())
    {
      auto* rep = qobject_cast<pqDataRepresentation*>(item);
      auto* domain = rep && rep->isVisible() ? qobject_cast<pqPipelineFilter*>(rep->getInput())
                                             : nullptr;
      if (!domain || std::strcmp(domain->getProxy()->GetXMLName(), "ReducedDomain") != 0)
      {
        continue;
      }
      for (pqOutputPort* port : domain->getInputs())
      {
        for (pqDataRepresentation* display : port->getRepresentations(nullptr))
        {
          auto pair = std::make_pair(view, display);
          if (isGaussianTFDisplay(display) &&
            std::find(wanted.begin(), wanted.end(), pair) == wanted.end())
          {
            wanted.push_back(pair);
          }
        }
      }
    }
  }

  // Keep the handles still wanted, drop the others, add the new pairs.
  std::vector<QPointer<pqGaussianWidgetHandles>> kept;
  for (auto& handles : this->Handles)
  {
    if (!handles)
    {
      continue;
    }
    auto pair = std::make_pair(handles->domainView(), handles->display());
    auto found = std::find(wanted.begin(), wanted.end(), pair);
    if (found != wanted.end())
    {
      wanted.erase(found);
      kept.push_back(handles);
    }
    else
    {
      delete handles;
    }
  }
  for (auto& pair : wanted)
  {
    kept.emplace_back(new pqGaussianWidgetHandles(pair.first, pair.second, this));
  }
  this->Handles = std::move(kept);
}

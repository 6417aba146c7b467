#include "pqBestViewpointActions.h"

#include "pqActiveObjects.h"
#include "pqCoreUtilities.h"
#include "pqPVApplicationCore.h"
#include "pqPipelineSource.h"
#include "pqPythonManager.h"
#include "pqRenderView.h"

#include <QAction>
#include <QIcon>
#include <QMessageBox>

//-----------------------------------------------------------------------------
pqBestViewpointActions::pqBestViewpointActions(QObject* parentObject)
  : Superclass(parentObject)
{
  this->BestViewpointAction =
    new QAction(QIcon(":/MultichannelExplorer/Icons/BestViewpoint.svg"), "Best Viewpoint", this);
  this->BestViewpointAction->setObjectName("actionMultichannelBestViewpoint");
  this->BestViewpointAction->setToolTip(
    "Best Viewpoint: turn the camera of the active view to the best view of the active "
    "volume (3D Harris interest points + PCA of its opacity, following the volume "
    "display's opacity function)");
  this->BestViewpointAction->setStatusTip(this->BestViewpointAction->toolTip());
  this->addAction(this->BestViewpointAction);
  this->setExclusive(false);

  QObject::connect(
    this->BestViewpointAction, &QAction::triggered, this, &pqBestViewpointActions::onTriggered);
  pqActiveObjects& active = pqActiveObjects::instance();
  QObject::connect(&active, &pqActiveObjects::sourceChanged, this,
    &pqBestViewpointActions::updateEnableState);
  QObject::connect(
    &active, &pqActiveObjects::viewChanged, this, &pqBestViewpointActions::updateEnableState);
  this->updateEnableState();
}

//-----------------------------------------------------------------------------
void pqBestViewpointActions::updateEnableState()
{
  pqActiveObjects& active = pqActiveObjects::instance();
  this->BestViewpointAction->setEnabled(
    active.activeSource() != nullptr && qobject_cast<pqRenderView*>(active.activeView()));
}

//-----------------------------------------------------------------------------
void pqBestViewpointActions::onTriggered()
{
  pqPVApplicationCore* core = pqPVApplicationCore::instance();
  pqPythonManager* python = core ? core->pythonManager() : nullptr;
  if (!python)
  {
    QMessageBox::warning(pqCoreUtilities::mainWidget(), "Best Viewpoint",
      "Best Viewpoint needs ParaView's Python support, which is not available.");
    return;
  }
  // Errors (no image data, flat volume...) are reported by the filter and the helper in
  // the Output Messages window; the camera stays as it was.
  python->executeCode("from paraview.simple import *\n"
                      "import multichannel_explorer\n"
                      "multichannel_explorer.apply_best_viewpoint(GetActiveSource(), "
                      "GetActiveView(), disambiguate=True)\n");
}

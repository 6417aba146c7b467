#include "pqBestViewpointActions.h"

#include "pqActiveObjects.h"
#include "pqCoreUtilities.h"
#include "pqExploreMultichannelActions.h"
#include "pqMultichannelProbe.h"
#include "pqPVApplicationCore.h"
#include "pqPipelineSource.h"
#include "pqPythonManager.h"
#include "pqRenderView.h"
#include "pqUndoStack.h"

#include <QAction>
#include <QIcon>
#include <QMessageBox>

//-----------------------------------------------------------------------------
pqBestViewpointActions::pqBestViewpointActions(QObject* parentObject)
  : Superclass(parentObject)
{
  // Explore Multichannel, Show Reduced Domain, Show Spectrum: the toolbar's first buttons.
  new pqExploreMultichannelActions(this);
  this->BestViewpointAction =
    new QAction(QIcon(":/MultichannelExplorer/Icons/BestViewpoint.svg"), "Best Viewpoint", this);
  this->BestViewpointAction->setObjectName("actionMultichannelBestViewpoint");
  this->BestViewpointAction->setIconText("Best View");
  this->BestViewpointAction->setToolTip(
    "Best Viewpoint: turn the camera of the active view to the best view of the active "
    "volume (3D Harris interest points + PCA of its opacity, following the volume "
    "display's opacity function)");
  this->BestViewpointAction->setStatusTip(this->BestViewpointAction->toolTip());
  this->addAction(this->BestViewpointAction);

  this->FollowAction = new QAction(
    QIcon(":/MultichannelExplorer/Icons/FollowBestViewpoint.svg"), "Follow Best Viewpoint", this);
  this->FollowAction->setObjectName("actionMultichannelFollowBestViewpoint");
  this->FollowAction->setIconText("Follow");
  this->FollowAction->setCheckable(true);
  this->FollowAction->setToolTip(
    "Follow Best Viewpoint: while on, the camera turns to the best view of the active "
    "\"Gaussian TF Volume\" display after every change of its Gaussian widgets");
  this->FollowAction->setStatusTip(this->FollowAction->toolTip());
  this->addAction(this->FollowAction);

  this->SeedWidgetsAction = new QAction(
    QIcon(":/MultichannelExplorer/Icons/SeedWidgets.svg"), "Seed Gaussian Widgets", this);
  this->SeedWidgetsAction->setObjectName("actionMultichannelSeedWidgets");
  this->SeedWidgetsAction->setIconText("Seed");
  this->SeedWidgetsAction->setToolTip(
    "Seed Gaussian Widgets: put 4 widgets at the k-means clusters of the reduced domain "
    "of the active \"Gaussian TF Volume\" display (a starting point to edit)");
  this->SeedWidgetsAction->setStatusTip(this->SeedWidgetsAction->toolTip());
  this->addAction(this->SeedWidgetsAction);
  new pqMultichannelProbe(this); // Probe, Add Widget Here, Brush Selection, in this toolbar
  // Short texts beside their icons (the full ones stay in menus and tooltips).
  for (QAction* action : this->actions())
  {
    if (action->objectName() == "actionMultichannelAddWidget")
    {
      action->setIconText("Add Here");
    }
    else if (action->objectName() == "actionMultichannelBrush")
    {
      action->setIconText("Brush");
    }
  }
  this->setExclusive(false);

  QObject::connect(
    this->FollowAction, &QAction::toggled, this, &pqBestViewpointActions::onFollowToggled);
  QObject::connect(
    this->SeedWidgetsAction, &QAction::triggered, this, &pqBestViewpointActions::onSeedWidgets);

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
  const bool enabled =
    active.activeSource() != nullptr && qobject_cast<pqRenderView*>(active.activeView());
  this->BestViewpointAction->setEnabled(enabled);
  this->SeedWidgetsAction->setEnabled(enabled);
  // Switching off stays possible whatever is active.
  this->FollowAction->setEnabled(enabled || this->FollowAction->isChecked());
}

//-----------------------------------------------------------------------------
bool pqBestViewpointActions::runPython(const char* title, const char* code)
{
  pqPVApplicationCore* core = pqPVApplicationCore::instance();
  pqPythonManager* python = core ? core->pythonManager() : nullptr;
  if (!python)
  {
    QMessageBox::warning(pqCoreUtilities::mainWidget(), title,
      QString("%1 needs ParaView's Python support, which is not available.").arg(title));
    return false;
  }
  python->executeCode(code);
  return true;
}

//-----------------------------------------------------------------------------
void pqBestViewpointActions::onFollowToggled(bool follow)
{
  // Without a Gaussian TF display the helper raises; the message goes to the Output
  // Messages window and the toggle is switched back off by the next check.
  if (!follow)
  {
    this->runPython("Follow Best Viewpoint",
      "import multichannel_explorer\n"
      "multichannel_explorer.stop_following()\n");
    return;
  }
  this->runPython("Follow Best Viewpoint",
    "from paraview.simple import *\n"
    "import multichannel_explorer\n"
    "multichannel_explorer.follow_best_viewpoint(GetActiveSource(), GetActiveView())\n");
}

//-----------------------------------------------------------------------------
void pqBestViewpointActions::onSeedWidgets()
{
  // One undo step named after what it does (not "Changed 'vtkSMSourceProxy'").
  SCOPED_UNDO_SET("Seed 4 Gaussian widgets");
  this->runPython("Seed Gaussian Widgets",
    "from paraview.simple import *\n"
    "import multichannel_explorer\n"
    "multichannel_explorer.auto_widgets(GetActiveSource(), 4, GetActiveView())\n"
    "Render()\n");
}

//-----------------------------------------------------------------------------
void pqBestViewpointActions::onTriggered()
{
  // Errors (no image data, flat volume...) are reported by the filter and the helper in
  // the Output Messages window; the camera stays as it was. The camera is not in the undo
  // stack; the BestViewpoint filter the helper makes is, as one step.
  SCOPED_UNDO_SET("Best Viewpoint");
  this->runPython("Best Viewpoint",
    "from paraview.simple import *\n"
    "import multichannel_explorer\n"
    "multichannel_explorer.apply_best_viewpoint(GetActiveSource(), "
    "GetActiveView(), disambiguate=True)\n");
}

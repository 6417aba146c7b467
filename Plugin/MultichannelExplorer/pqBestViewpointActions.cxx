#include "pqBestViewpointActions.h"

#include "pqActiveObjects.h"
#include "pqExploreMultichannelActions.h"
#include "pqMultichannelProbe.h"
#include "pqMultichannelPython.h"
#include "pqMultichannelToolbarAction.h"
#include "pqPipelineSource.h"
#include "pqRenderView.h"
#include "pqUndoStack.h"

#include <QAction>

//-----------------------------------------------------------------------------
pqBestViewpointActions::pqBestViewpointActions(QObject* parentObject)
  : Superclass(parentObject)
{
  // Explore Multichannel, Show Reduced Domain, Show Spectrum: the toolbar's first buttons.
  new pqExploreMultichannelActions(this);
  this->BestViewpointAction =
    pqMultichannelToolbarAction::add(this, this, "actionMultichannelBestViewpoint");
  this->FollowAction =
    pqMultichannelToolbarAction::add(this, this, "actionMultichannelFollowBestViewpoint");
  this->SeedWidgetsAction =
    pqMultichannelToolbarAction::add(this, this, "actionMultichannelSeedWidgets");
  new pqMultichannelProbe(this); // Probe, Add Widget Here, Brush Selection, in this toolbar
  this->setExclusive(false);

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
void pqBestViewpointActions::onFollowToggled(bool follow)
{
  // Without a Gaussian TF display the helper raises; the message goes to the Output
  // Messages window and the toggle is switched back off by the next check.
  if (!follow)
  {
    pqMultichannelPython::run("Follow Best Viewpoint",
      "import multichannel_explorer\n"
      "multichannel_explorer.stop_following()\n");
    return;
  }
  pqMultichannelPython::run("Follow Best Viewpoint",
    "from paraview.simple import *\n"
    "import multichannel_explorer\n"
    "multichannel_explorer.follow_best_viewpoint(GetActiveSource(), GetActiveView())\n");
}

//-----------------------------------------------------------------------------
void pqBestViewpointActions::onSeedWidgets()
{
  // One undo step named after what it does (not "Changed 'vtkSMSourceProxy'").
  SCOPED_UNDO_SET("Seed 4 Gaussian widgets");
  pqMultichannelPython::run("Seed Gaussian Widgets",
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
  pqMultichannelPython::run("Best Viewpoint",
    "from paraview.simple import *\n"
    "import multichannel_explorer\n"
    "multichannel_explorer.apply_best_viewpoint(GetActiveSource(), "
    "GetActiveView(), disambiguate=True)\n");
}

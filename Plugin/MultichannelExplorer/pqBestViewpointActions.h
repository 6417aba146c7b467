// Toolbar "Multichannel Explorer": Best Viewpoint, Follow Best Viewpoint, Seed Widgets (after
// pqExploreMultichannelActions' Explore, Domain and Spectrum)
// (and pqMultichannelProbe's Probe, Add Widget Here and Brush Selection).
#ifndef pqBestViewpointActions_h
#define pqBestViewpointActions_h

#include <QActionGroup>

/**
 * The toolbar's actions run the plugin's Python helpers in ParaView's Python interpreter,
 * so the GUI and scripts share one implementation (the Python package
 * Plugin/MultichannelExplorer/multichannel_explorer/). Enabled when there is an active
 * source and an active render view.
 * - "Best Viewpoint": apply_best_viewpoint(GetActiveSource(), GetActiveView(),
 *   disambiguate=True); for a "Gaussian TF Volume" display the opacity is its widgets'.
 * - "Follow Best Viewpoint" (a toggle): follow_best_viewpoint on the active source's
 *   "Gaussian TF Volume" display: the camera turns to the best view after every change
 *   of its widgets, until the toggle is switched off (stop_following()). The turn is the
 *   helper's animation (turn_camera: about 0.5 s of rendered steps on the sphere, the
 *   view-up carried along, of v and -v the one nearer the camera), the same as in scripts.
 * - "Seed Gaussian Widgets": auto_widgets(display, 4): widgets at the k-means clusters
 *   of the reduced domain.
 */
class pqBestViewpointActions : public QActionGroup
{
  Q_OBJECT
  typedef QActionGroup Superclass;

public:
  pqBestViewpointActions(QObject* parent);
  ~pqBestViewpointActions() override = default;

private Q_SLOTS:
  void onTriggered();
  void onFollowToggled(bool follow);
  void onSeedWidgets();
  void updateEnableState();

private:
  Q_DISABLE_COPY(pqBestViewpointActions)

  QAction* BestViewpointAction;
  QAction* FollowAction;
  QAction* SeedWidgetsAction;
};

#endif

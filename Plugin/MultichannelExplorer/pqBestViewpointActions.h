// Toolbar "Multichannel Explorer": the "Best Viewpoint" button.
#ifndef pqBestViewpointActions_h
#define pqBestViewpointActions_h

#include <QActionGroup>

/**
 * One action, "Best Viewpoint": runs
 *   multichannel_explorer.apply_best_viewpoint(GetActiveSource(), GetActiveView(),
 *                                              disambiguate=True)
 * in ParaView's Python interpreter, so the GUI and scripts share one implementation
 * (Plugin/MultichannelExplorer/multichannel_explorer.py). Enabled when there is an
 * active source and an active render view.
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
  void updateEnableState();

private:
  Q_DISABLE_COPY(pqBestViewpointActions)
  QAction* BestViewpointAction;
};

#endif

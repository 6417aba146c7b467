// Puts draggable Gaussian-widget handles into every render view that shows a reduced
// domain (the plugin's auto-start: created when the plugin loads in the GUI).
#ifndef pqGaussianWidgetHandlesBehavior_h
#define pqGaussianWidgetHandlesBehavior_h

#include <QObject>
#include <QPointer>
#include <QTimer>

#include <vector>

class pqGaussianWidgetHandles;
class pqProxy;
class pqRepresentation;

/**
 * Watches the pipeline for the dual domain: a render view showing (a visible
 * representation of) a ReducedDomain filter whose input is shown, visible, as a
 * "Gaussian TF Volume" in some view. For each such pair (domain view, volume display) it
 * keeps one pqGaussianWidgetHandles; pairs that go away (view closed, representation
 * hidden or switched, filter deleted) lose their handles. The pairs are recomputed,
 * coalesced, after any representation, view or property change.
 *
 * The handles are client-side VTK widgets on the domain view's interactor (as ParaView's
 * own 3D widgets) and write the display's GaussianWidgets through its proxy, so they work
 * in the builtin session and against a pvserver (docs/gaussian-widget-handles.md says
 * what was tried).
 */
class pqGaussianWidgetHandlesBehavior : public QObject
{
  Q_OBJECT
  typedef QObject Superclass;

public:
  pqGaussianWidgetHandlesBehavior(QObject* parent = nullptr);
  ~pqGaussianWidgetHandlesBehavior() override;

  // pqAutoStartInterface (paraview_plugin_add_auto_start).
  void startup();
  void shutdown();

private Q_SLOTS:
  void scheduleUpdate() { this->UpdateTimer.start(); }
  void updateHandles();
  void watch(pqProxy* item);

private:
  Q_DISABLE_COPY(pqGaussianWidgetHandlesBehavior)
  QTimer UpdateTimer;
  std::vector<QPointer<pqGaussianWidgetHandles>> Handles;
};

#endif

// Toolbar "Multichannel Explorer": Probe (a toggle), Add Widget Here and Brush Selection.
#ifndef pqMultichannelProbe_h
#define pqMultichannelProbe_h

#include <QList>
#include <QObject>
#include <QPoint>
#include <QPointer>

class QAction;
class QActionGroup;
class QLabel;
class QWidget;
class pqView;

/**
 * Links the volume and its reduced domain from the GUI through the plugin's Python helpers
 * (multichannel_explorer.picking / brushing), so the GUI and scripts share one
 * implementation:
 * - "Probe" (a toggle): while on, a left click (press and release without a drag, so the
 *   camera still turns on a drag) in a render view probes the pixel: in the volume view
 *   probe_at_pixel (the voxel seen there through the "Gaussian TF Volume" display), in
 *   the domain view probe_domain_at_pixel (the voxel of the cloud point there); the voxel
 *   is marked in both views. Its values appear in a small label over the view (at the
 *   bottom, right of the orientation axes' corner, in the view's lower half, so neither
 *   the axes nor the widget legend, which keeps to the upper half from the top right
 *   corner, is under it; at the bottom right instead when it would cover the probed
 *   pixel; object name "MultichannelProbeLabel")
 *   until the next probe or the toggle goes off; the hourglass cursor shows while the helper works, and the views are rendered
 *   with the markers once the label is up. The click also makes the view active
 *   (ParaView's own handling of the press).
 * - "Add Widget Here": add_widget_at the last probed voxel's reduced coordinates (a
 *   palette colour no widget has, sigma 5% of the coordinates' range, opacity 0.5).
 * - "Brush Selection": brush(GetActiveSource()): the points selected in the domain view
 *   (ParaView's rubber band, e.g. Select Points Through) highlighted as voxels in the
 *   volume view; the count appears in the same label.
 */
class pqMultichannelProbe : public QObject
{
  Q_OBJECT
  typedef QObject Superclass;

public:
  // Adds the three actions to `group` (the toolbar's action group), which owns this object.
  pqMultichannelProbe(QActionGroup* group);
  ~pqMultichannelProbe() override = default;

protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

private Q_SLOTS:
  void onProbeToggled(bool on);
  void onBrush();
  void onAddWidget();
  void watchView(pqView* view);
  void watchAllViews();

private:
  Q_DISABLE_COPY(pqMultichannelProbe)
  // Runs `code` in ParaView's Python, then returns the text the helper left in
  // multichannel_explorer._gui.text (empty when Python is missing).
  QString runPython(const QString& code);
  // `probed`: the clicked point in the view widget's coordinates, which the label keeps
  // clear of; none for Brush and Add Widget Here.
  void showText(QWidget* viewWidget, const QString& text, const QPoint* probed = nullptr);
  // Bottom left of its view, below the view's middle, or bottom right when that covers
  // the probed point (again at every resize of the view).
  void placeLabel();

  QAction* ProbeAction;
  QAction* AddWidgetAction;
  QAction* BrushAction;
  QList<QPointer<QWidget>> Watched;
  QPointer<QLabel> Label;
  QPoint PressPosition;
  bool Pressed = false;
  QPoint ProbedPoint; // the label keeps clear of it while HasProbedPoint
  bool HasProbedPoint = false;
};

#endif

// The dock panel "Gaussian Widgets": the widget editor of the active "Gaussian TF Volume"
// display, one click away (View > Gaussian Widgets), and a word in the view when it has no
// widgets.
#ifndef pqGaussianWidgetsDock_h
#define pqGaussianWidgetsDock_h

#include <QDockWidget>
#include <QPointer>

#include <vtkNew.h>

class QLabel;
class QVBoxLayout;
class pqDataRepresentation;
class pqPropertyWidget;
class vtkEventQtSlotConnect;

/**
 * Follows the active representation (pqActiveObjects): when it is a "Gaussian TF Volume"
 * display, the panel holds the same editor as the Properties panel
 * (pqGaussianWidgetsPropertyWidget on its GaussianWidgets property: edits apply at once,
 * each one undo step); otherwise it says how to get one. When the active display draws
 * nothing because it has no widgets, a label over its view says how to add them (it goes
 * away as soon as widgets exist, whoever adds them: the editor, a script, undo).
 * Registered with paraview_plugin_add_dock_window; it becomes a tab beside the Properties
 * panel.
 */
class pqGaussianWidgetsDock : public QDockWidget
{
  Q_OBJECT
  typedef QDockWidget Superclass;

public:
  pqGaussianWidgetsDock(const QString& title, QWidget* parent = nullptr,
    Qt::WindowFlags flags = Qt::WindowFlags());
  pqGaussianWidgetsDock(QWidget* parent = nullptr, Qt::WindowFlags flags = Qt::WindowFlags());
  ~pqGaussianWidgetsDock() override;

private Q_SLOTS:
  /** The active representation changed: follow it. */
  void setRepresentation(pqDataRepresentation* representation);
  /** Its representation type or widgets changed: editor or message, view label. */
  void refresh();

private:
  Q_DISABLE_COPY(pqGaussianWidgetsDock)
  void constructor();
  bool isGaussianTF() const;

  QPointer<pqDataRepresentation> Representation;
  QPointer<pqPropertyWidget> Editor;
  QPointer<QLabel> ViewLabel;
  QLabel* Message;
  int Attempts = 0;
  QVBoxLayout* Layout;
  vtkNew<vtkEventQtSlotConnect> Connections;
};

#endif

#include "pqMultichannelProbe.h"

#include "pqMultichannelPython.h"
#include "pqMultichannelToolbarAction.h"

#include "pqActiveObjects.h"
#include "pqApplicationCore.h"
#include "pqRenderView.h"
#include "pqServerManagerModel.h"
#include "pqUndoStack.h"

#include <QAction>
#include <QActionGroup>
#include <QApplication>
#include <QCursor>
#include <QEvent>
#include <QLabel>
#include <QMouseEvent>
#include <QRect>
#include <QWidget>

#include <algorithm>

//-----------------------------------------------------------------------------
pqMultichannelProbe::pqMultichannelProbe(QActionGroup* group)
  : Superclass(group)
{
  this->ProbeAction = pqMultichannelToolbarAction::add(group, this, "actionMultichannelProbe");
  this->AddWidgetAction =
    pqMultichannelToolbarAction::add(group, this, "actionMultichannelAddWidget");
  this->BrushAction = pqMultichannelToolbarAction::add(group, this, "actionMultichannelBrush");
  // Views made while probing are watched too.
  QObject::connect(pqApplicationCore::instance()->getServerManagerModel(),
    &pqServerManagerModel::viewAdded, this, &pqMultichannelProbe::watchView);
}

//-----------------------------------------------------------------------------
void pqMultichannelProbe::onProbeToggled(bool on)
{
  for (QWidget* widget : this->Watched)
  {
    if (widget)
    {
      widget->removeEventFilter(this);
    }
  }
  this->Watched.clear();
  if (on)
  {
    this->watchAllViews();
  }
  else if (this->Label)
  {
    this->Label->hide();
  }
}

//-----------------------------------------------------------------------------
void pqMultichannelProbe::watchAllViews()
{
  // Every render view: the volume view and the domain view can both be probed, and the
  // first click in either probes (it also makes that view the active one).
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  for (pqRenderView* view : model->findItems<pqRenderView*>())
  {
    this->watchView(view);
  }
}

//-----------------------------------------------------------------------------
void pqMultichannelProbe::watchView(pqView* view)
{
  pqRenderView* renderView = qobject_cast<pqRenderView*>(view);
  QWidget* widget = renderView ? renderView->widget() : nullptr;
  if (this->ProbeAction->isChecked() && widget && !this->Watched.contains(widget))
  {
    widget->installEventFilter(this);
    this->Watched.append(widget);
  }
}

//-----------------------------------------------------------------------------
bool pqMultichannelProbe::eventFilter(QObject* watched, QEvent* event)
{
  // Never consumes the event: a drag still turns the camera, a click also probes.
  QWidget* widget = qobject_cast<QWidget*>(watched);
  if (widget && event->type() == QEvent::Resize && this->Label &&
    widget == this->Label->parentWidget())
  {
    this->placeLabel();
  }
  if (widget && this->Watched.contains(widget) &&
    (event->type() == QEvent::MouseButtonPress || event->type() == QEvent::MouseButtonRelease))
  {
    QMouseEvent* mouse = static_cast<QMouseEvent*>(event);
    if (mouse->button() == Qt::LeftButton && event->type() == QEvent::MouseButtonPress)
    {
      this->PressPosition = mouse->pos();
      this->Pressed = true;
    }
    else if (mouse->button() == Qt::LeftButton && this->Pressed)
    {
      this->Pressed = false;
      if ((mouse->pos() - this->PressPosition).manhattanLength() <= 3)
      {
        // VTK display coordinates: device pixels, origin at the bottom left. The press
        // made this view the active one, which the helper probes.
        const double ratio = widget->devicePixelRatioF();
        const int x = static_cast<int>(mouse->pos().x() * ratio);
        const int y = static_cast<int>((widget->height() - 1 - mouse->pos().y()) * ratio);
        // A probe changes no data the user made (only the marker it keeps): no undo step,
        // so Edit > Undo after a probe undoes the user's last edit.
        SCOPED_UNDO_EXCLUDE();
        const QString text = this->runPython(
          QString("import multichannel_explorer._gui\n"
                  "multichannel_explorer._gui.probe(%1, %2)\n")
            .arg(x)
            .arg(y));
        const QPoint probed = mouse->pos();
        this->showText(widget, text, &probed);
        // The markers: drawn once the answer is up (the helper does not render).
        pqApplicationCore::instance()->render();
      }
    }
  }
  return Superclass::eventFilter(watched, event);
}

//-----------------------------------------------------------------------------
void pqMultichannelProbe::onBrush()
{
  SCOPED_UNDO_SET("Brush Selection");
  const QString text = this->runPython("import multichannel_explorer._gui\n"
                                       "multichannel_explorer._gui.brush()\n");
  pqView* view = pqActiveObjects::instance().activeView();
  if (view && view->widget())
  {
    this->showText(view->widget(), text);
  }
}

//-----------------------------------------------------------------------------
void pqMultichannelProbe::onAddWidget()
{
  QString text;
  {
    SCOPED_UNDO_SET("Add Gaussian Widget Here");
    text = this->runPython("import multichannel_explorer._gui\n"
                           "multichannel_explorer._gui.add_widget()\n");
  }
  pqView* view = pqActiveObjects::instance().activeView();
  if (view && view->widget())
  {
    this->showText(view->widget(), text);
  }
}

//-----------------------------------------------------------------------------
QString pqMultichannelProbe::runPython(const QString& code)
{
  // The hourglass while the helper works (a probe reads one voxel back from the server;
  // Add Widget Here and Brush Selection read a sample).
  QApplication::setOverrideCursor(QCursor(Qt::WaitCursor));
  const bool ran = pqMultichannelPython::run("Probe", code);
  QApplication::restoreOverrideCursor();
  return ran ? pqMultichannelPython::text("multichannel_explorer._gui", "text") : QString();
}

//-----------------------------------------------------------------------------
void pqMultichannelProbe::showText(QWidget* viewWidget, const QString& text, const QPoint* probed)
{
  this->HasProbedPoint = probed != nullptr;
  this->ProbedPoint = probed ? *probed : QPoint();
  if (!this->Label || this->Label->parentWidget() != viewWidget)
  {
    delete this->Label;
    this->Label = new QLabel(viewWidget);
    this->Label->setObjectName("MultichannelProbeLabel");
    this->Label->setStyleSheet("QLabel { background: rgba(20, 20, 20, 200); color: white; "
                               "padding: 6px; font-family: monospace; }");
    this->Label->setAttribute(Qt::WA_TransparentForMouseEvents);
    viewWidget->installEventFilter(this); // its resizes move the label (placeLabel)
    // The label's "Widget N added" goes when that widget is undone.
    if (pqUndoStack* stack = pqApplicationCore::instance()->getUndoStack())
    {
      QLabel* label = this->Label;
      QObject::connect(stack, &pqUndoStack::undone, label, [label]() {
        if (label->text().startsWith("Widget "))
        {
          label->hide();
        }
      });
    }
  }
  if (text.isEmpty())
  {
    this->Label->hide();
    return;
  }
  this->Label->setText(text);
  this->Label->adjustSize();
  this->placeLabel();
  this->Label->show();
  this->Label->raise();
}

//-----------------------------------------------------------------------------
void pqMultichannelProbe::placeLabel()
{
  // Three things share the view's corners: ParaView's orientation axes (shown by default)
  // are a square a quarter of the view's height tall at the bottom left corner
  // (vtkPVAxesWidget keeps its viewport square); the widget legend
  // (vtkGaussianTFVolumeRepresentation) hangs 10 pixels below the top right corner and is
  // at most half the view tall, so it ends above the middle + 10 pixels. The label sits 8
  // pixels above the bottom edge, right of where the axes are (whether or not they are on
  // now, so that switching them on never puts them under it), and never higher than the
  // middle + 12 pixels. A view too narrow for the label right of the axes gets it as far
  // right as it fits (over the axes rather than cut); a label taller than the lower half
  // (a view under about twice its height) is cut at the view's bottom edge. Where it
  // would cover the probed pixel (and the marker drawn there), it goes to the bottom
  // right corner if that keeps clear of it (12 pixels around).
  const QWidget* view = this->Label->parentWidget();
  const int width = view->width();
  const int height = view->height();
  const int besideAxes = height / 4 + 8;
  const int rightmost = std::max(8, width - this->Label->width() - 8);
  int x = besideAxes + this->Label->width() + 8 <= width ? besideAxes : rightmost;
  const int y = std::max(height / 2 + 12, height - this->Label->height() - 8);
  auto covers = [this, y](int left) {
    return QRect(QPoint(left, y), this->Label->size())
      .adjusted(-12, -12, 12, 12)
      .contains(this->ProbedPoint);
  };
  if (this->HasProbedPoint && covers(x) && !covers(rightmost))
  {
    x = rightmost;
  }
  this->Label->move(x, y);
}

// Draggable handles for the Gaussian widgets of one "Gaussian TF Volume" display, in one
// render view that shows that display's reduced domain (the ReducedDomain filter).
#ifndef pqGaussianWidgetHandles_h
#define pqGaussianWidgetHandles_h

#include <QObject>
#include <QPointer>

#include "vtkSmartPointer.h"
#include "vtkWeakPointer.h"

#include <vector>

class pqDataRepresentation;
class pqRenderView;
class vtkObject;
class vtkRenderWindowInteractor;
class vtkSMProxy;
class vtkSphereWidget2;

/**
 * One vtkSphereWidget2 per Gaussian widget (8 values of the display's GaussianWidgets:
 * cx, cy, cz, sigma, r, g, b, opacity): a wireframe sphere of radius sigma in the widget's
 * colour at its centre, on the domain view's interactor (client side, like ParaView's own
 * 3D widgets).
 * - left drag on a sphere: moves the centre (in the plane facing the camera);
 * - shift + left drag, or right drag, on a sphere: scales sigma (vtkSphereWidget2's
 *   scaling: drag up to grow, down to shrink);
 * - mouse wheel over a sphere: sigma x 1.1 per notch forward, / 1.1 backward (the camera
 *   does not zoom then).
 * While dragging, every move writes the widget back into GaussianWidgets and renders the
 * volume's view; a drag (or one wheel notch) is one undo step. The grabbed widget becomes
 * pqGaussianWidgetSelection's selection (the widget editor highlights its row); the
 * selected widget's sphere is drawn with thick, opaque lines.
 * Any other change of GaussianWidgets (editor, Python, undo) moves the handles.
 */
class pqGaussianWidgetHandles : public QObject
{
  Q_OBJECT
  typedef QObject Superclass;

public:
  pqGaussianWidgetHandles(pqRenderView* domainView, pqDataRepresentation* display,
    QObject* parent = nullptr);
  ~pqGaussianWidgetHandles() override;

  pqRenderView* domainView() const;
  pqDataRepresentation* display() const;

  /** Number of handles shown (one per complete widget of GaussianWidgets). */
  int numberOfHandles() const { return static_cast<int>(this->Widgets.size()); }

private Q_SLOTS:
  // GaussianWidgets changed: move, resize and recolour the handles (or rebuild them when
  // the number of widgets changed). Ignored while this object writes the property itself.
  void updateHandles();
  // Handles take no mouse events while the view is in a selection (or zoom-to-box) mode:
  // a rubber band started over a large sphere must select, not drag the widget.
  void updateInteractivity();
  void highlightSelection();

private:
  bool handlesTakeEvents() const;
  void showEditorOfDisplay();
  Q_DISABLE_COPY(pqGaussianWidgetHandles)

  vtkSMProxy* proxy() const;
  std::vector<double> values() const;
  void rebuild(int count);
  int indexOf(vtkObject* widget) const;
  void styleHandle(int index, bool selected);

  // vtkSphereWidget2 events.
  void onStartInteraction(vtkObject* caller, unsigned long, void*);
  void onInteraction(vtkObject* caller, unsigned long, void*);
  void onEndInteraction(vtkObject* caller, unsigned long, void*);
  // The interactor's wheel events, seen before the camera's.
  // True (the event is aborted) when the wheel resized a handle.
  bool onWheel(vtkObject* caller, unsigned long event, void*);

  // Handle `index` -> GaussianWidgets (centre, sigma), then render the volume.
  void writeBack(int index);

  QPointer<pqRenderView> DomainView;
  QPointer<pqDataRepresentation> Display;
  vtkWeakPointer<vtkRenderWindowInteractor> Interactor;
  std::vector<vtkSmartPointer<vtkSphereWidget2>> Widgets;
  unsigned long WheelForwardTag = 0;
  unsigned long WheelBackwardTag = 0;
  unsigned long PropertyTag = 0;
  unsigned long InteractionModeTag = 0;
  bool Moved = false; // the handle in hand moved since it was grabbed
  bool Writing = false; // this object is setting GaussianWidgets
  int Dragged = -1;     // handle being dragged, -1: none
};

#endif

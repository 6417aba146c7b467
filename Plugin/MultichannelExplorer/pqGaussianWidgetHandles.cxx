#include "pqGaussianWidgetHandles.h"

#include "pqGaussianWidgetSelection.h"

#include "pqActiveObjects.h"
#include "pqCoreUtilities.h"
#include "pqPipelineSource.h"
#include "pqDataRepresentation.h"
#include "pqRenderView.h"
#include "pqUndoStack.h"
#include "pqView.h"
#include "vtkCommand.h"
#include "vtkEvent.h"
#include "vtkNew.h"
#include "vtkPVRenderView.h"
#include "vtkProperty.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkSMProperty.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMProxy.h"
#include "vtkSMRenderViewProxy.h"
#include "vtkSphereRepresentation.h"
#include "vtkSphereWidget2.h"
#include "vtkWidgetEvent.h"
#include "vtkWidgetEventTranslator.h"

#include <cmath>

namespace
{
constexpr int ValuesPerWidget = 8; // cx, cy, cz, sigma, r, g, b, opacity
constexpr double WheelFactor = 1.1;

vtkSphereRepresentation* sphereOf(vtkSphereWidget2* widget)
{
  return vtkSphereRepresentation::SafeDownCast(widget->GetRepresentation());
}
}

//-----------------------------------------------------------------------------
pqGaussianWidgetHandles::pqGaussianWidgetHandles(
  pqRenderView* domainView, pqDataRepresentation* display, QObject* parentObject)
  : Superclass(parentObject)
  , DomainView(domainView)
  , Display(display)
{
  vtkSMRenderViewProxy* viewProxy = domainView->getRenderViewProxy();
  this->Interactor = viewProxy->GetInteractor();
  if (this->Interactor)
  {
    // Above the widgets (0.5) and the camera style (0): a wheel over a handle resizes it
    // instead of zooming.
    this->WheelForwardTag = this->Interactor->AddObserver(
      vtkCommand::MouseWheelForwardEvent, this, &pqGaussianWidgetHandles::onWheel, 1.0f);
    this->WheelBackwardTag = this->Interactor->AddObserver(
      vtkCommand::MouseWheelBackwardEvent, this, &pqGaussianWidgetHandles::onWheel, 1.0f);
  }
  if (vtkSMProperty* prop = this->proxy()->GetProperty("GaussianWidgets"))
  {
    this->PropertyTag =
      pqCoreUtilities::connect(prop, vtkCommand::ModifiedEvent, this, SLOT(updateHandles()));
  }
  if (vtkSMProperty* mode = viewProxy->GetProperty("InteractionMode"))
  {
    this->InteractionModeTag = pqCoreUtilities::connect(
      mode, vtkCommand::ModifiedEvent, this, SLOT(updateInteractivity()));
  }
  QObject::connect(pqGaussianWidgetSelection::instance(),
    &pqGaussianWidgetSelection::selectionChanged, this,
    &pqGaussianWidgetHandles::highlightSelection);
  this->updateHandles();
}

//-----------------------------------------------------------------------------
bool pqGaussianWidgetHandles::handlesTakeEvents() const
{
  vtkSMProxy* viewProxy = this->DomainView ? this->DomainView->getProxy() : nullptr;
  if (!viewProxy || !viewProxy->GetProperty("InteractionMode"))
  {
    return true;
  }
  const int mode = vtkSMPropertyHelper(viewProxy, "InteractionMode").GetAsInt();
  return mode != vtkPVRenderView::INTERACTION_MODE_SELECTION &&
    mode != vtkPVRenderView::INTERACTION_MODE_ZOOM &&
    mode != vtkPVRenderView::INTERACTION_MODE_POLYGON;
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetHandles::updateInteractivity()
{
  const bool take = this->handlesTakeEvents();
  for (auto& widget : this->Widgets)
  {
    widget->SetProcessEvents(take ? 1 : 0);
  }
}

//-----------------------------------------------------------------------------
pqGaussianWidgetHandles::~pqGaussianWidgetHandles()
{
  if (this->Dragged >= 0)
  {
    END_UNDO_SET(); // a view closed mid-drag must not leave the undo set open
  }
  this->rebuild(0);
  if (this->Interactor)
  {
    this->Interactor->RemoveObserver(this->WheelForwardTag);
    this->Interactor->RemoveObserver(this->WheelBackwardTag);
  }
  // pqCoreUtilities::connect cleans up its observer when this object goes away.
  if (this->DomainView)
  {
    this->DomainView->render(); // the handles leave the picture, not only the interactor
  }
}

//-----------------------------------------------------------------------------
pqRenderView* pqGaussianWidgetHandles::domainView() const
{
  return this->DomainView;
}

//-----------------------------------------------------------------------------
pqDataRepresentation* pqGaussianWidgetHandles::display() const
{
  return this->Display;
}

//-----------------------------------------------------------------------------
vtkSMProxy* pqGaussianWidgetHandles::proxy() const
{
  return this->Display ? this->Display->getProxy() : nullptr;
}

//-----------------------------------------------------------------------------
std::vector<double> pqGaussianWidgetHandles::values() const
{
  vtkSMProxy* proxy = this->proxy();
  return proxy ? vtkSMPropertyHelper(proxy, "GaussianWidgets").GetDoubleArray()
               : std::vector<double>();
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetHandles::rebuild(int count)
{
  for (auto& widget : this->Widgets)
  {
    widget->SetEnabled(0);
    widget->RemoveAllObservers();
  }
  this->Widgets.clear();
  vtkPVRenderView* pvview = this->DomainView
    ? vtkPVRenderView::SafeDownCast(this->DomainView->getRenderViewProxy()->GetClientSideObject())
    : nullptr;
  if (!this->Interactor || !pvview)
  {
    return;
  }
  // The non-composited renderer is where ParaView's own 3D widgets draw (on top of the
  // data, picked on the client).
  vtkRenderer* renderer = pvview->GetRenderer(vtkPVRenderView::NON_COMPOSITED_RENDERER);
  for (int i = 0; i < count; ++i)
  {
    vtkNew<vtkSphereRepresentation> rep;
    rep->SetRepresentationToWireframe();
    rep->HandleVisibilityOff();
    rep->HandleTextOff();
    rep->RadialLineOff();
    rep->SetThetaResolution(24);
    rep->SetPhiResolution(12);
    vtkNew<vtkSphereWidget2> widget;
    widget->SetInteractor(this->Interactor);
    widget->SetCurrentRenderer(renderer);
    widget->SetRepresentation(rep);
    // Shift + left drag scales (the plain widget would translate), like its right drag.
    vtkWidgetEventTranslator* translator = widget->GetEventTranslator();
    translator->RemoveTranslation(vtkCommand::LeftButtonPressEvent);
    translator->SetTranslation(vtkCommand::LeftButtonPressEvent, vtkEvent::NoModifier, 0, 0,
      nullptr, vtkWidgetEvent::Select);
    translator->SetTranslation(vtkCommand::LeftButtonPressEvent, vtkEvent::ShiftModifier, 0, 0,
      nullptr, vtkWidgetEvent::Scale);
    widget->AddObserver(
      vtkCommand::StartInteractionEvent, this, &pqGaussianWidgetHandles::onStartInteraction);
    widget->AddObserver(
      vtkCommand::InteractionEvent, this, &pqGaussianWidgetHandles::onInteraction);
    widget->AddObserver(
      vtkCommand::EndInteractionEvent, this, &pqGaussianWidgetHandles::onEndInteraction);
    this->Widgets.emplace_back(widget);
  }
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetHandles::updateHandles()
{
  if (this->Writing)
  {
    return;
  }
  const std::vector<double> v = this->values();
  const int count = static_cast<int>(v.size()) / ValuesPerWidget;
  if (this->Dragged >= count)
  {
    // The widget being dragged went away (e.g. the editor removed it): end the drag.
    END_UNDO_SET();
    this->Dragged = -1;
  }
  if (count != this->numberOfHandles())
  {
    this->rebuild(count);
  }
  for (int i = 0; i < count; ++i)
  {
    const double* w = v.data() + ValuesPerWidget * i;
    vtkSphereRepresentation* rep = sphereOf(this->Widgets[i]);
    // An invalid sigma (the representation reports it) still gets a visible handle.
    const double sigma = std::isfinite(w[3]) && w[3] > 0 ? w[3] : 1.0;
    double centre[3] = { w[0], w[1], w[2] };
    double handle[3] = { w[0] + sigma, w[1], w[2] };
    if (i != this->Dragged)
    {
      rep->PlaceWidget(centre, handle);
    }
    for (vtkProperty* prop : { rep->GetSphereProperty(), rep->GetSelectedSphereProperty() })
    {
      prop->SetColor(w[4], w[5], w[6]);
      prop->SetAmbient(1.0); // flat colour: the widget's own, whatever the lights
      prop->SetDiffuse(0.0);
    }
  }
  for (auto& widget : this->Widgets)
  {
    widget->SetEnabled(1);
  }
  this->updateInteractivity();
  this->highlightSelection();
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetHandles::styleHandle(int index, bool selected)
{
  // Opaque lines in both cases: translucent wireframes came out washed-out white in the
  // view's non-composited renderer (seen under Mesa). Selected: thick and full colour;
  // others: thin and a little darker. The selected property (used while dragging) keeps
  // the widget's full colour.
  vtkSphereRepresentation* rep = sphereOf(this->Widgets[index]);
  vtkProperty* full = rep->GetSelectedSphereProperty();
  full->SetLineWidth(4.0);
  double colour[3];
  full->GetColor(colour);
  const double shade = selected ? 1.0 : 0.75;
  vtkProperty* prop = rep->GetSphereProperty();
  prop->SetColor(shade * colour[0], shade * colour[1], shade * colour[2]);
  prop->SetLineWidth(selected ? 4.0 : 1.0);
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetHandles::highlightSelection()
{
  pqGaussianWidgetSelection* selection = pqGaussianWidgetSelection::instance();
  const int selected = selection->representation() == this->proxy() ? selection->index() : -1;
  for (int i = 0; i < this->numberOfHandles(); ++i)
  {
    this->styleHandle(i, i == selected);
  }
  if (this->DomainView)
  {
    this->DomainView->render();
  }
}

//-----------------------------------------------------------------------------
int pqGaussianWidgetHandles::indexOf(vtkObject* widget) const
{
  for (int i = 0; i < this->numberOfHandles(); ++i)
  {
    if (this->Widgets[i] == widget)
    {
      return i;
    }
  }
  return -1;
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetHandles::onStartInteraction(vtkObject* caller, unsigned long, void*)
{
  const int index = this->indexOf(caller);
  if (index < 0 || this->Dragged >= 0)
  {
    return;
  }
  const bool scaling = sphereOf(this->Widgets[index])->GetInteractionState() ==
    vtkSphereRepresentation::Scaling;
  BEGIN_UNDO_SET(QString(scaling ? "Resize Gaussian Widget %1" : "Move Gaussian Widget %1")
                   .arg(index + 1));
  this->Dragged = index;
  this->Moved = false;
  pqGaussianWidgetSelection::instance()->select(this->proxy(), index);
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetHandles::onInteraction(vtkObject* caller, unsigned long, void*)
{
  const int index = this->indexOf(caller);
  if (index >= 0 && index == this->Dragged)
  {
    this->writeBack(index);
    this->Moved = true;
  }
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetHandles::onEndInteraction(vtkObject* caller, unsigned long, void*)
{
  const int index = this->indexOf(caller);
  if (index < 0 || index != this->Dragged)
  {
    return;
  }
  this->writeBack(index);
  this->Dragged = -1;
  END_UNDO_SET();
  if (this->Moved)
  {
    // Only after a real drag: a plain click (e.g. a probe in the domain view) keeps the
    // view it was made in.
    this->showEditorOfDisplay();
  }
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetHandles::showEditorOfDisplay()
{
  // A click in the domain view makes it the active view, and the Properties panel then
  // shows the (absent) display of the source there: hand the panel back to the volume's
  // view and source, so the widget editor shows the grabbed widget's row highlighted.
  pqView* volumeView = this->Display ? this->Display->getView() : nullptr;
  if (volumeView && pqActiveObjects::instance().activeView() != volumeView)
  {
    pqActiveObjects::instance().setActiveView(volumeView);
    pqActiveObjects::instance().setActiveSource(this->Display->getInput());
  }
}

//-----------------------------------------------------------------------------
bool pqGaussianWidgetHandles::onWheel(vtkObject*, unsigned long event, void*)
{
  if (!this->Interactor || this->Dragged >= 0 || !this->handlesTakeEvents())
  {
    return false;
  }
  const int* pos = this->Interactor->GetEventPosition();
  // The selected handle first: where handles overlap, the wheel resizes the one in hand.
  pqGaussianWidgetSelection* selection = pqGaussianWidgetSelection::instance();
  const int selected = selection->representation() == this->proxy() ? selection->index() : -1;
  int hit = -1;
  for (int k = -1; k < this->numberOfHandles() && hit < 0; ++k)
  {
    const int i = k < 0 ? selected : k;
    if (i < 0 || i >= this->numberOfHandles())
    {
      continue;
    }
    vtkSphereRepresentation* rep = sphereOf(this->Widgets[i]);
    if (rep->ComputeInteractionState(pos[0], pos[1]) != vtkSphereRepresentation::Outside)
    {
      hit = i;
    }
    rep->SetInteractionState(vtkSphereRepresentation::Outside);
  }
  if (hit < 0)
  {
    return false; // not over a handle: the camera zooms as usual
  }
  vtkSphereRepresentation* rep = sphereOf(this->Widgets[hit]);
  const double factor =
    event == vtkCommand::MouseWheelForwardEvent ? WheelFactor : 1.0 / WheelFactor;
  rep->SetRadius(rep->GetRadius() * factor);
  BEGIN_UNDO_SET(QString("Resize Gaussian Widget %1").arg(hit + 1));
  selection->select(this->proxy(), hit);
  this->writeBack(hit);
  END_UNDO_SET();
  if (this->DomainView)
  {
    this->DomainView->render();
  }
  return true; // handled: no zoom
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetHandles::writeBack(int index)
{
  vtkSMProxy* proxy = this->proxy();
  std::vector<double> v = this->values();
  if (!proxy || ValuesPerWidget * (index + 1) > static_cast<int>(v.size()))
  {
    return;
  }
  vtkSphereRepresentation* rep = sphereOf(this->Widgets[index]);
  double centre[3];
  rep->GetCenter(centre);
  double* w = v.data() + ValuesPerWidget * index;
  w[0] = centre[0];
  w[1] = centre[1];
  w[2] = centre[2];
  w[3] = rep->GetRadius();
  this->Writing = true;
  vtkSMPropertyHelper(proxy, "GaussianWidgets").Set(v.data(), static_cast<unsigned int>(v.size()));
  proxy->UpdateVTKObjects();
  this->Writing = false;
  // Per-sample classification makes this a uniform update: cheap enough for every move.
  if (pqView* view = this->Display->getView())
  {
    view->render();
  }
}

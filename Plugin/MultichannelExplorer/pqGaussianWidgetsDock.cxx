#include "pqGaussianWidgetsDock.h"

#include "pqActiveObjects.h"
#include "pqDataRepresentation.h"
#include "pqGaussianWidgetsPropertyWidget.h"
#include "pqView.h"
#include "vtkCommand.h"
#include "vtkEventQtSlotConnect.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMProxy.h"

#include <QLabel>
#include <QMainWindow>
#include <QTimer>
#include <QScrollArea>
#include <QVBoxLayout>
#include <QWidget>

#include <algorithm>

namespace
{
const char* const GaussianTF = "Gaussian TF Volume";
const char* const NoDisplay =
  "No Gaussian TF Volume is active.\n\n"
  "Select the channel readers (or one multichannel volume) and press Explore Multichannel "
  "in the Multichannel Explorer toolbar, or show a DimensionReduction output as "
  "\"Gaussian TF Volume\" (Representation box) and click it in the Pipeline Browser.";
const char* const NoWidgets =
  "No Gaussian widgets: the volume is transparent. Press Seed (toolbar) or \"Seed from "
  "clusters\" in the Gaussian Widgets panel, or Add there.";
}

//-----------------------------------------------------------------------------
pqGaussianWidgetsDock::pqGaussianWidgetsDock(
  const QString& title, QWidget* parentObject, Qt::WindowFlags flags)
  : Superclass(title, parentObject, flags)
{
  this->constructor();
}

//-----------------------------------------------------------------------------
pqGaussianWidgetsDock::pqGaussianWidgetsDock(QWidget* parentObject, Qt::WindowFlags flags)
  : Superclass(parentObject, flags)
{
  this->constructor();
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetsDock::constructor()
{
  this->setWindowTitle("Gaussian Widgets");
  this->setObjectName("GaussianWidgetsDock");
  auto* scroll = new QScrollArea(this);
  scroll->setObjectName("GaussianWidgetsScroll");
  scroll->setWidgetResizable(true);
  // The tab beside Properties must not widen the left dock area (a scroll area's size hint
  // is as wide as its rows): the views keep their width.
  scroll->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Preferred);
  auto* content = new QWidget(scroll);
  content->setObjectName("GaussianWidgetsContent");
  this->Layout = new QVBoxLayout(content);
  this->Message = new QLabel(NoDisplay, content);
  this->Message->setObjectName("GaussianWidgetsDockMessage");
  this->Message->setWordWrap(true);
  this->Layout->addWidget(this->Message);
  this->Layout->addStretch(1);
  scroll->setWidget(content);
  this->setWidget(scroll);

  // A tab beside the Properties panel (the views keep their width; Explore Multichannel
  // raises this tab), once ParaView has put the dock into the main window.
  auto* retry = new QTimer(this);
  retry->setInterval(100);
  QObject::connect(retry, &QTimer::timeout, this, [this, retry]() {
    auto* window = qobject_cast<QMainWindow*>(this->parentWidget());
    auto* properties = window ? window->findChild<QDockWidget*>("propertiesDock") : nullptr;
    if (properties && window->dockWidgetArea(this) != Qt::NoDockWidgetArea &&
      window->dockWidgetArea(properties) != Qt::NoDockWidgetArea)
    {
      window->tabifyDockWidget(properties, this);
      properties->raise();
    }
    if (properties || ++this->Attempts > 200)
    {
      retry->stop();
      retry->deleteLater();
    }
  });
  retry->start();

  QObject::connect(&pqActiveObjects::instance(),
    QOverload<pqDataRepresentation*>::of(&pqActiveObjects::representationChanged), this,
    &pqGaussianWidgetsDock::setRepresentation);
  this->setRepresentation(pqActiveObjects::instance().activeRepresentation()
      ? qobject_cast<pqDataRepresentation*>(pqActiveObjects::instance().activeRepresentation())
      : nullptr);
}

//-----------------------------------------------------------------------------
pqGaussianWidgetsDock::~pqGaussianWidgetsDock()
{
  delete this->ViewLabel;
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetsDock::setRepresentation(pqDataRepresentation* representation)
{
  if (representation == this->Representation && (this->Editor || !this->isGaussianTF()))
  {
    this->refresh();
    return;
  }
  this->Connections->Disconnect();
  this->Representation = representation;
  delete this->Editor;
  vtkSMProxy* proxy = representation ? representation->getProxy() : nullptr;
  if (proxy && proxy->GetProperty("Representation"))
  {
    // A change of the representation type, of the widgets or of the visibility can turn
    // the editor or the view's label on or off.
    for (const char* name : { "Representation", "GaussianWidgets", "Visibility" })
    {
      if (vtkSMProperty* property = proxy->GetProperty(name))
      {
        this->Connections->Connect(property, vtkCommand::ModifiedEvent, this, SLOT(refresh()),
          nullptr, 0.0, Qt::QueuedConnection);
      }
    }
  }
  this->refresh();
}

//-----------------------------------------------------------------------------
bool pqGaussianWidgetsDock::isGaussianTF() const
{
  vtkSMProxy* proxy = this->Representation ? this->Representation->getProxy() : nullptr;
  if (!proxy || !proxy->GetProperty("Representation") || !proxy->GetProperty("GaussianWidgets"))
  {
    return false;
  }
  const char* type = vtkSMPropertyHelper(proxy, "Representation").GetAsString();
  return type && QString(type) == GaussianTF;
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetsDock::refresh()
{
  const bool gaussian = this->isGaussianTF();
  vtkSMProxy* proxy = gaussian ? this->Representation->getProxy() : nullptr;
  if (gaussian && !this->Editor)
  {
    this->Editor = new pqGaussianWidgetsPropertyWidget(
      proxy, proxy->GetProperty("GaussianWidgets"), this->widget()->findChild<QWidget*>(
                                                      "GaussianWidgetsContent"));
    this->Editor->setObjectName("GaussianWidgetsDockEditor");
    this->Editor->setView(this->Representation->getView());
    this->Layout->insertWidget(1, this->Editor);
  }
  else if (!gaussian && this->Editor)
  {
    delete this->Editor;
  }
  this->Message->setVisible(!gaussian);

  // The word in the view: a visible Gaussian TF display without widgets draws nothing.
  const bool empty = gaussian && vtkSMPropertyHelper(proxy, "Visibility").GetAsInt() != 0 &&
    vtkSMPropertyHelper(proxy, "GaussianWidgets").GetNumberOfElements() == 0;
  QWidget* viewWidget = (empty && this->Representation->getView())
    ? this->Representation->getView()->widget()
    : nullptr;
  if (!viewWidget)
  {
    if (this->ViewLabel)
    {
      this->ViewLabel->hide();
    }
    return;
  }
  if (!this->ViewLabel || this->ViewLabel->parentWidget() != viewWidget)
  {
    delete this->ViewLabel;
    this->ViewLabel = new QLabel(NoWidgets, viewWidget);
    this->ViewLabel->setObjectName("GaussianTFNoWidgetsLabel");
    this->ViewLabel->setWordWrap(true);
    this->ViewLabel->setStyleSheet("QLabel { background: rgba(20, 20, 20, 200); color: white; "
                                   "padding: 8px; }");
    this->ViewLabel->setAttribute(Qt::WA_TransparentForMouseEvents);
  }
  // Top left, as the probe's label: the place does not depend on the view's size.
  this->ViewLabel->setFixedWidth(std::max(200, std::min(460, viewWidget->width() - 16)));
  this->ViewLabel->adjustSize();
  this->ViewLabel->move(8, 8);
  this->ViewLabel->show();
  this->ViewLabel->raise();
}

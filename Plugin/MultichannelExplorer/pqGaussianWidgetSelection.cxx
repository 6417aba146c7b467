#include "pqGaussianWidgetSelection.h"

#include "pqApplicationCore.h"
#include "pqServerManagerModel.h"
#include "pqProxy.h"

pqGaussianWidgetSelection::pqGaussianWidgetSelection(QObject* parent)
  : Superclass(parent)
{
  // A representation that goes away takes its selection with it.
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  QObject::connect(model, &pqServerManagerModel::proxyRemoved, this, [this](pqProxy* proxy) {
    if (proxy && proxy->getProxy() == this->Representation)
    {
      this->select(nullptr, -1);
    }
  });
}

pqGaussianWidgetSelection* pqGaussianWidgetSelection::instance()
{
  static QPointer<pqGaussianWidgetSelection> selection;
  if (!selection)
  {
    selection = new pqGaussianWidgetSelection(pqApplicationCore::instance());
  }
  return selection;
}

void pqGaussianWidgetSelection::select(vtkSMProxy* representation, int index)
{
  if (!representation)
  {
    index = -1;
  }
  if (representation == this->Representation && index == this->Index)
  {
    return;
  }
  this->Representation = representation;
  this->Index = index;
  Q_EMIT this->selectionChanged(representation, index);
}

#include "pqMultichannelPropertyWidget.h"

#include <QLabel>
#include <QVBoxLayout>

//-----------------------------------------------------------------------------
pqMultichannelPropertyWidget::pqMultichannelPropertyWidget(vtkSMProxy* smproxy,
  vtkSMProperty* smproperty, QWidget* parentWidget, const char* objectName, bool showLabel)
  : Superclass(smproxy, parentWidget)
{
  if (objectName)
  {
    this->setObjectName(objectName);
  }
  this->setProperty(smproperty);
  this->setShowLabel(showLabel);
  this->PanelLayout = new QVBoxLayout(this);
  this->PanelLayout->setContentsMargins(0, 0, 0, 0);
}

//-----------------------------------------------------------------------------
QLabel* pqMultichannelPropertyWidget::addMessageLabel(const char* objectName)
{
  auto* label = new QLabel(this);
  label->setObjectName(objectName);
  label->setWordWrap(true);
  this->PanelLayout->addWidget(label);
  return label;
}

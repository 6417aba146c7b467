#include "pqMultichannelToolbarAction.h"

#include <QAction>
#include <QActionGroup>
#include <QIcon>

//-----------------------------------------------------------------------------
QAction* pqMultichannelToolbarAction::add(QActionGroup* group, const char* icon,
  const QString& text, const QString& iconText, const char* objectName, const QString& toolTip)
{
  auto* action = new QAction(
    QIcon(QString(":/MultichannelExplorer/Icons/%1.svg").arg(icon)), text, group);
  action->setIconText(iconText);
  action->setObjectName(objectName);
  action->setToolTip(toolTip);
  action->setStatusTip(toolTip);
  group->addAction(action);
  return action;
}

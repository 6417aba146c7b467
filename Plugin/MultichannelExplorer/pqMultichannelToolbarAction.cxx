#include "pqMultichannelToolbarAction.h"

#include <QAction>
#include <QActionGroup>
#include <QFile>
#include <QIcon>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QMetaMethod>
#include <QtDebug>

namespace
{
// The table, read once from the plugin's resources (pqBestViewpoint.qrc).
const QJsonArray& toolbarTable()
{
  static const QJsonArray table = [] {
    QFile file(":/MultichannelExplorer/ToolbarActions.json");
    if (!file.open(QIODevice::ReadOnly))
    {
      qWarning() << "pqMultichannelToolbarAction: cannot open" << file.fileName();
      return QJsonArray();
    }
    return QJsonDocument::fromJson(file.readAll()).array();
  }();
  return table;
}
}

//-----------------------------------------------------------------------------
QAction* pqMultichannelToolbarAction::add(
  QActionGroup* group, QObject* receiver, const char* objectName)
{
  QJsonObject entry;
  for (const QJsonValue& value : toolbarTable())
  {
    if (value.toObject().value("objectName").toString() == objectName)
    {
      entry = value.toObject();
    }
  }
  if (entry.isEmpty())
  {
    qWarning() << "pqMultichannelToolbarAction: no entry" << objectName
               << "in ToolbarActions.json";
  }
  auto* action = new QAction(
    QIcon(QString(":/MultichannelExplorer/Icons/%1.svg").arg(entry.value("icon").toString())),
    entry.value("text").toString(objectName), group);
  action->setIconText(entry.value("iconText").toString());
  action->setObjectName(objectName);
  action->setToolTip(entry.value("toolTip").toString());
  action->setStatusTip(entry.value("toolTip").toString());
  const bool toggle = entry.value("toggle").toBool();
  action->setCheckable(toggle);
  group->addAction(action);

  // The slot by its name in the table: slot() for a plain action, slot(bool) for a toggle.
  const QByteArray slot = entry.value("slot").toString().toLatin1() + (toggle ? "(bool)" : "()");
  const QMetaObject* meta = receiver->metaObject();
  const int index = meta->indexOfSlot(slot.constData());
  if (index < 0)
  {
    qWarning() << "pqMultichannelToolbarAction:" << meta->className() << "has no slot" << slot
               << "for" << objectName;
    return action;
  }
  QObject::connect(action,
    toggle ? QMetaMethod::fromSignal(&QAction::toggled)
           : QMetaMethod::fromSignal(&QAction::triggered),
    receiver, meta->method(index));
  return action;
}

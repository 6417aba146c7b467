// The actions of the plugin's toolbar (Explore Multichannel, Best Viewpoint, Probe, ...) are
// made the same way: made here once.
#ifndef pqMultichannelToolbarAction_h
#define pqMultichannelToolbarAction_h

#include <QString>

class QAction;
class QActionGroup;

namespace pqMultichannelToolbarAction
{
/**
 * A new action in `group` (its parent too): the icon Icons/`icon`.svg of the plugin's
 * resources, `text` (menus), `iconText` (the short text beside the icon in the toolbar),
 * `objectName` (the GUI tests find the action by it) and `toolTip`, also the status tip.
 */
QAction* add(QActionGroup* group, const char* icon, const QString& text, const QString& iconText,
  const char* objectName, const QString& toolTip);
}

#endif

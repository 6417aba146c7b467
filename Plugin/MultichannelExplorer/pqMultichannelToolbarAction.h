// The actions of the plugin's toolbar (Explore Multichannel, Best Viewpoint, Probe, ...): one
// table, ToolbarActions.json (in the plugin's resources), and one way to make each action.
#ifndef pqMultichannelToolbarAction_h
#define pqMultichannelToolbarAction_h

class QAction;
class QActionGroup;
class QObject;

namespace pqMultichannelToolbarAction
{
/**
 * A new action in `group` (its parent too), made from the entry `objectName` of the table
 * ToolbarActions.json, which lists every action in the toolbar's order: its icon
 * (Icons/<icon>.svg of the plugin's resources), text (menus), icon text (the short text
 * beside the icon in the toolbar), tool tip (also the status tip), and the slot of
 * `receiver` it runs: `slot()` when triggered, or, for a toggle (`"toggle": true`, the
 * action checkable), `slot(bool)` at each change of its state. The GUI tests find the action
 * by its `objectName`. A name or slot missing from the table is a warning, not a stop.
 */
QAction* add(QActionGroup* group, QObject* receiver, const char* objectName);
}

#endif

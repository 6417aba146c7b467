// Makes ParaView's own Python state (File > Save State as .py) load this plugin from the
// moment the plugin loads in the GUI (the plugin's auto-start).
#ifndef pqMultichannelStateBehavior_h
#define pqMultichannelStateBehavior_h

#include <QObject>

/**
 * A Python state names the readers and filters it creates but no plugin, so a state of a
 * session that used this plugin fails in a session without it. Importing the package
 * multichannel_explorer installs a hook on paraview.smstate.get_state (what
 * pqSaveStateReaction's Python state runs, through vtkSMTrace::GetState) that puts the
 * plugin's LoadPlugin lines at the top of the state. The GUI's buttons import the package
 * when first pressed; this behavior imports it as soon as the plugin is loaded, so a
 * state saved before any button was pressed (filters created from the Filters menu) loads
 * the plugin too. A failed import is reported in the Output Messages window.
 */
class pqMultichannelStateBehavior : public QObject
{
  Q_OBJECT
  typedef QObject Superclass;

public:
  pqMultichannelStateBehavior(QObject* parent = nullptr);
  ~pqMultichannelStateBehavior() override = default;

  // pqAutoStartInterface (paraview_plugin_add_auto_start).
  void startup();
  void shutdown() {}

private:
  Q_DISABLE_COPY(pqMultichannelStateBehavior)
};

#endif

#include "pqMultichannelStateBehavior.h"

#include "pqMultichannelPython.h"

#include <QTimer>

//-----------------------------------------------------------------------------
pqMultichannelStateBehavior::pqMultichannelStateBehavior(QObject* parentObject)
  : Superclass(parentObject)
{
}

//-----------------------------------------------------------------------------
void pqMultichannelStateBehavior::startup()
{
  // After the plugin's loading has finished (a plugin auto-loaded at start-up waits for the
  // application to be set up). A plugin's Python modules are found through the importer
  // that paraview.servermanager installs (sys.meta_path), which the GUI's Python may not
  // have imported yet.
  QTimer::singleShot(0, this, []() {
    if (pqMultichannelPython::importModule("paraview.servermanager"))
    {
      pqMultichannelPython::importModule("multichannel_explorer");
    }
  });
}

// Running the plugin's Python helpers from its GUI classes and reading back what they left.
#ifndef pqMultichannelPython_h
#define pqMultichannelPython_h

#include <QString>

/**
 * The GUI's buttons run the package multichannel_explorer in ParaView's Python (one
 * implementation for scripts and the GUI). These run code through pqPythonManager (errors
 * go to the Output Messages window) and read a module attribute back.
 */
namespace pqMultichannelPython
{
/** Runs `code`; false, with a message box titled `title`, when Python is not available. */
bool run(const QString& title, const QString& code);

/** str(module.attribute), or "" when the module or attribute is missing or no string. */
QString text(const char* module, const char* attribute);

/** bool(module.attribute); false when missing. */
bool flag(const char* module, const char* attribute);

/** Imports `module` in ParaView's Python; false, with Python's error printed (the Output
 * Messages window in the GUI), when the import fails. */
bool importModule(const char* module);
}

#endif

// Python.h must come before the standard headers (it sets feature macros).
#include "vtkPython.h"

#include "pqMultichannelPython.h"

#include "pqCoreUtilities.h"
#include "pqPVApplicationCore.h"
#include "pqPythonManager.h"
#include "vtkPythonInterpreter.h"

#include <QMessageBox>

namespace
{
// A new reference to module.attribute, or nullptr (the Python error cleared).
PyObject* attribute(const char* module, const char* name)
{
  PyObject* mod = PyImport_ImportModule(module);
  PyObject* value = mod ? PyObject_GetAttrString(mod, name) : nullptr;
  Py_XDECREF(mod);
  PyErr_Clear();
  return value;
}
}

//-----------------------------------------------------------------------------
bool pqMultichannelPython::run(const QString& title, const QString& code)
{
  pqPVApplicationCore* core = pqPVApplicationCore::instance();
  pqPythonManager* python = core ? core->pythonManager() : nullptr;
  if (!python)
  {
    QMessageBox::warning(pqCoreUtilities::mainWidget(), title,
      QString("%1 needs ParaView's Python support, which is not available.").arg(title));
    return false;
  }
  python->executeCode(code.toUtf8());
  return true;
}

//-----------------------------------------------------------------------------
QString pqMultichannelPython::text(const char* module, const char* name)
{
  vtkPythonInterpreter::Initialize();
  vtkPythonScopeGilEnsurer gil;
  QString result;
  PyObject* value = attribute(module, name);
  if (value && PyUnicode_Check(value))
  {
    result = QString::fromUtf8(PyUnicode_AsUTF8(value));
  }
  Py_XDECREF(value);
  PyErr_Clear();
  return result;
}

//-----------------------------------------------------------------------------
bool pqMultichannelPython::flag(const char* module, const char* name)
{
  vtkPythonInterpreter::Initialize();
  vtkPythonScopeGilEnsurer gil;
  PyObject* value = attribute(module, name);
  const bool result = value && PyObject_IsTrue(value) == 1;
  Py_XDECREF(value);
  PyErr_Clear();
  return result;
}

//-----------------------------------------------------------------------------
bool pqMultichannelPython::importModule(const char* module)
{
  vtkPythonInterpreter::Initialize();
  vtkPythonScopeGilEnsurer gil;
  PyObject* mod = PyImport_ImportModule(module);
  if (!mod)
  {
    PyErr_Print();
    return false;
  }
  Py_DECREF(mod);
  return true;
}

#include "pqExploreMultichannelActions.h"

#include "pqMultichannelToolbarAction.h"

#include "pqActiveObjects.h"
#include "pqApplicationCore.h"
#include "pqCoreUtilities.h"
#include "pqGaussianWidgetsDock.h"
#include "pqMultichannelPython.h"
#include "pqOutputPort.h"
#include "pqPipelineSource.h"
#include "pqProxyGroupMenuManager.h"
#include "pqRenderView.h"
#include "pqServerManagerModel.h"
#include "pqUndoStack.h"
#include "vtkSMProxy.h"

#include <QAction>
#include <QActionGroup>
#include <QApplication>
#include <QMainWindow>
#include <QMenu>
#include <QMenuBar>
#include <QMessageBox>
#include <QStatusBar>
#include <QTimer>
#include <QToolBar>
#include <QToolButton>

namespace
{
const char* const Module = "multichannel_explorer.exploration";
// The toolbar pqPluginActionGroupBehavior makes for GROUP_NAME "ToolBar/Multichannel Explorer".
const char* const ToolBarName = "Multichannel Explorer";

QMainWindow* mainWindow()
{
  return qobject_cast<QMainWindow*>(pqCoreUtilities::mainWidget());
}

QString withoutAmpersands(QString text)
{
  return text.remove('&');
}
}

//-----------------------------------------------------------------------------
pqExploreMultichannelActions::pqExploreMultichannelActions(QActionGroup* group)
  : Superclass(group)
{
  this->ExploreAction = pqMultichannelToolbarAction::add(group, this, "actionMultichannelExplore");
  this->ShowDomainAction =
    pqMultichannelToolbarAction::add(group, this, "actionMultichannelShowDomain");
  this->SpectrumAction =
    pqMultichannelToolbarAction::add(group, this, "actionMultichannelSpectrum");
  pqActiveObjects& active = pqActiveObjects::instance();
  QObject::connect(&active, &pqActiveObjects::selectionChanged, this,
    &pqExploreMultichannelActions::updateEnableState);
  QObject::connect(&active, &pqActiveObjects::viewChanged, this,
    &pqExploreMultichannelActions::updateEnableState);
  this->updateEnableState();

  // The toolbar and the Filters menu's categories exist once the plugin's interfaces are
  // all in place and the main window is built: after this constructor, at a moment that
  // depends on how the plugin was loaded. Try until both are done (at most 20 s).
  auto* retry = new QTimer(this);
  retry->setInterval(100);
  QObject::connect(retry, &QTimer::timeout, this, [this, retry]() {
    const bool done = this->styleToolBar() & this->addToFiltersMenu();
    if (done || ++this->Attempts > 200)
    {
      retry->stop();
      retry->deleteLater();
    }
  });
  retry->start();
}

//-----------------------------------------------------------------------------
void pqExploreMultichannelActions::updateEnableState()
{
  // Enabled whenever a pipeline exists: what is missing is said by the helper, in words.
  pqActiveObjects& active = pqActiveObjects::instance();
  const bool anything = !active.selection().isEmpty() || active.activeSource() != nullptr;
  const bool renderView = qobject_cast<pqRenderView*>(active.activeView()) != nullptr;
  this->ExploreAction->setEnabled(anything && (renderView || active.activeView() == nullptr));
  this->ShowDomainAction->setEnabled(anything && renderView);
  this->SpectrumAction->setEnabled(anything);
}

//-----------------------------------------------------------------------------
bool pqExploreMultichannelActions::styleToolBar()
{
  QMainWindow* window = mainWindow();
  QToolBar* toolbar = window ? window->findChild<QToolBar*>(ToolBarName) : nullptr;
  if (!toolbar || !toolbar->actions().contains(this->ExploreAction))
  {
    return false;
  }
  toolbar->setToolButtonStyle(Qt::ToolButtonTextBesideIcon);
  // A row of its own: with their text the buttons need the window's width, and none
  // should hide behind the overflow arrow.
  if (window->toolBarArea(toolbar) == Qt::TopToolBarArea && !window->toolBarBreak(toolbar))
  {
    window->removeToolBar(toolbar);
    window->addToolBarBreak(Qt::TopToolBarArea);
    window->addToolBar(Qt::TopToolBarArea, toolbar);
    toolbar->show();
  }
  // Stable names for test playback: "<action name>Button" instead of a position.
  for (QAction* action : toolbar->actions())
  {
    if (QWidget* button = toolbar->widgetForAction(action))
    {
      if (!action->objectName().isEmpty())
      {
        button->setObjectName(action->objectName() + "Button");
      }
    }
  }
  return true;
}

//-----------------------------------------------------------------------------
bool pqExploreMultichannelActions::addToFiltersMenu()
{
  QMainWindow* window = mainWindow();
  QMenu* filters = window ? window->findChild<QMenu*>("menuFilters") : nullptr;
  if (!filters)
  {
    return false;
  }
  // Repopulating the menu (a plugin loaded, ...) drops the actions: put them back.
  auto* manager = filters->findChild<pqProxyGroupMenuManager*>();
  if (manager && !this->WatchingMenu)
  {
    this->WatchingMenu = true;
    QObject::connect(manager, &pqProxyGroupMenuManager::menuPopulated, this,
      &pqExploreMultichannelActions::addToFiltersMenu, Qt::QueuedConnection);
  }
  QMenu* multichannel = nullptr;
  for (QAction* action : filters->actions())
  {
    if (action->menu() && withoutAmpersands(action->text()) == "Multichannel")
    {
      multichannel = action->menu();
      break;
    }
  }
  if (!multichannel)
  {
    return false;
  }
  if (multichannel->actions().contains(this->ExploreAction))
  {
    return true;
  }
  QAction* first = multichannel->actions().isEmpty() ? nullptr : multichannel->actions()[0];
  multichannel->insertAction(first, this->ExploreAction);
  multichannel->insertAction(first, this->ShowDomainAction);
  multichannel->insertAction(first, this->SpectrumAction);
  multichannel->insertSeparator(first);
  this->FiltersSubmenu = multichannel;
  return true;
}

//-----------------------------------------------------------------------------
void pqExploreMultichannelActions::showStatus(const QString& text, int milliseconds)
{
  if (QMainWindow* window = mainWindow())
  {
    window->statusBar()->showMessage(text, milliseconds);
  }
}

//-----------------------------------------------------------------------------
void pqExploreMultichannelActions::onExplore()
{
  // The selection's sources (a selected output port stands for its source), in order.
  QStringList ids;
  for (pqServerManagerModelItem* item : pqActiveObjects::instance().selection())
  {
    pqPipelineSource* source = qobject_cast<pqPipelineSource*>(item);
    if (pqOutputPort* port = qobject_cast<pqOutputPort*>(item))
    {
      source = port->getSource();
    }
    if (source && !ids.contains(QString::number(source->getProxy()->GetGlobalID())))
    {
      ids << QString::number(source->getProxy()->GetGlobalID());
    }
  }
  if (ids.isEmpty() && pqActiveObjects::instance().activeSource())
  {
    ids << QString::number(pqActiveObjects::instance().activeSource()->getProxy()->GetGlobalID());
  }

  QApplication::setOverrideCursor(Qt::WaitCursor);
  BEGIN_UNDO_SET("Explore Multichannel");
  bool ran = pqMultichannelPython::run("Explore Multichannel",
    QString("import multichannel_explorer.exploration as _x\n"
            "_x._gui_begin([%1])\n"
            "del _x\n")
      .arg(ids.join(", ")));
  // One step per call, its description in the status bar while it runs. The exploration
  // has 6 steps; the bound only matters when Python cannot run the module at all.
  for (int step = 0; ran && step < 20 && !pqMultichannelPython::flag(Module, "done"); ++step)
  {
    this->showStatus(pqMultichannelPython::text(Module, "text"), 0);
    QApplication::processEvents(QEventLoop::ExcludeUserInputEvents);
    ran = pqMultichannelPython::run("Explore Multichannel",
      "import multichannel_explorer.exploration as _x\n"
      "_x._gui_step()\n"
      "del _x\n");
  }
  END_UNDO_SET();
  QApplication::restoreOverrideCursor();
  if (!ran)
  {
    return;
  }
  const QString text = pqMultichannelPython::text(Module, "text");
  if (pqMultichannelPython::flag(Module, "failed") || !pqMultichannelPython::flag(Module, "done"))
  {
    this->showStatus(QString(), 0);
    QMessageBox::warning(pqCoreUtilities::mainWidget(), "Explore Multichannel",
      text.isEmpty() ? QString("Explore Multichannel did not finish: see the Output Messages "
                               "window.")
                     : text);
    return;
  }
  // Readers opened but never applied now feed the exploration: they are applied (the
  // Properties panel would otherwise keep asking for Apply on them).
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  for (pqPipelineSource* source : model->findItems<pqPipelineSource*>())
  {
    if (source->modifiedState() == pqProxy::UNINITIALIZED && source->getNumberOfConsumers() > 0)
    {
      source->setModifiedState(pqProxy::UNMODIFIED);
    }
  }
  this->showStatus(text, 30000);
  if (QMainWindow* window = mainWindow())
  {
    if (auto* dock = window->findChild<pqGaussianWidgetsDock*>())
    {
      dock->show();
      dock->raise();
    }
  }
}

//-----------------------------------------------------------------------------
void pqExploreMultichannelActions::runHelper(const QString& title, const QString& call)
{
  QApplication::setOverrideCursor(Qt::WaitCursor);
  bool ran;
  {
    SCOPED_UNDO_SET(title);
    ran = pqMultichannelPython::run(title,
      QString("import multichannel_explorer.exploration as _x\n"
              "_x.%1()\n"
              "del _x\n")
        .arg(call));
  }
  QApplication::restoreOverrideCursor();
  if (!ran)
  {
    return;
  }
  const QString text = pqMultichannelPython::text(Module, "text");
  if (text.startsWith(title + ":"))
  {
    QMessageBox::warning(pqCoreUtilities::mainWidget(), title, text);
    return;
  }
  this->showStatus(text, 30000);
}

//-----------------------------------------------------------------------------
void pqExploreMultichannelActions::onShowDomain()
{
  this->runHelper("Show Reduced Domain", "_gui_show_domain");
}

//-----------------------------------------------------------------------------
void pqExploreMultichannelActions::onShowSpectrum()
{
  this->runHelper("Show Spectrum", "_gui_show_spectrum");
}

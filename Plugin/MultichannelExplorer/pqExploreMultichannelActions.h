// "Explore Multichannel", "Show Reduced Domain" and "Show Spectrum": the first exploration
// in one click, in the toolbar "Multichannel Explorer" and in Filters > Multichannel.
#ifndef pqExploreMultichannelActions_h
#define pqExploreMultichannelActions_h

#include <QObject>
#include <QPointer>

class QAction;
class QActionGroup;
class QMenu;

/**
 * The actions run the Python helpers of multichannel_explorer.exploration (the same
 * steps a script gets from explore_multichannel), each inside one named undo set, with
 * the hourglass cursor and the step that runs in the status bar:
 * - "Explore Multichannel": on the selected sources (several channel readers on one grid,
 *   merged with MergeChannels; one lone channel reader is joined by the other unused
 *   readers on its grid) or one multichannel volume: DimensionReduction with its defaults
 *   (features computed from the channels; ParaView's progress bar runs), the volume as a
 *   "Gaussian TF Volume" with 4 seeded widgets, its reduced domain beside it (split
 *   view, widget spheres draggable), the camera at the best view, and the reduction
 *   active so that the "Gaussian Widgets" panel shows its editor. Every piece is named
 *   after the inputs ("Exploration of ch2 + aal + brodmann") and is one undo step
 *   "Explore Multichannel". Readers that were waiting for Apply are marked applied.
 * - "Show Reduced Domain": show_dual_domain on the active Gaussian TF Volume display
 *   (widgets seeded first when it has none).
 * - "Show Spectrum": the upstream DimensionReduction's eigenvalue spectrum as a bar chart
 *   (component vs eigenvalue) below the active view.
 *
 * Python does the work (the helpers exist and are tested for scripts; doing it again in
 * C++ with vtkSMParaViewPipelineController would be a second implementation to keep equal).
 *
 * The class also gives the toolbar its text beside the icons (on a row of its own, every
 * button visible and named after its action for test playback) and puts the actions
 * at the top of Filters > Multichannel (again after every repopulation of that menu).
 */
class pqExploreMultichannelActions : public QObject
{
  Q_OBJECT
  typedef QObject Superclass;

public:
  /** Adds the actions to `group` (the toolbar's action group), which owns this object. */
  pqExploreMultichannelActions(QActionGroup* group);
  ~pqExploreMultichannelActions() override = default;

  QAction* exploreAction() const { return this->ExploreAction; }

private Q_SLOTS:
  void onExplore();
  void onShowDomain();
  void onShowSpectrum();
  void updateEnableState();
  /** Text beside icons, one row, named buttons; false while the toolbar is missing. */
  bool styleToolBar();
  /** The actions at the top of Filters > Multichannel; false while that menu is missing. */
  bool addToFiltersMenu();

private:
  Q_DISABLE_COPY(pqExploreMultichannelActions)
  /** Runs a one-call helper of exploration in an undo set; its text to the status bar,
   * or in a message box when it names a problem (`title` + ":" starts its text). */
  void runHelper(const QString& title, const QString& call);
  void showStatus(const QString& text, int milliseconds);

  QAction* ExploreAction;
  QAction* ShowDomainAction;
  QAction* SpectrumAction;
  QPointer<QMenu> FiltersSubmenu;
  int Attempts = 0;
  bool WatchingMenu = false;
};

#endif

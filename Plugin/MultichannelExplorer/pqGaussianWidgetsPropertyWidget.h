// The Properties-panel editor of a "Gaussian TF Volume" display's GaussianWidgets
// (panel_widget="gaussian_widgets_editor"): one pqGaussianWidgetRow per widget, buttons to
// add, duplicate, remove and seed widgets, and to save and load them as a transfer-function
// file (.mcvtf, with the reduction model they live in: multichannel_explorer.
// save_transfer_function / load_transfer_function).
//
// Storage: the flat GaussianWidgets property (8 numbers per widget) stays what is drawn
// and what Python sees. A hidden widget is written with opacity 0, and the opacity it gets
// back when shown again goes to GaussianWidgetsHidden (one number per widget: -1 shown,
// else the remembered opacity; empty when every widget is shown). Both are ordinary
// properties of the representation, so state files and undo keep them.
//
// Edits apply at once: each is pushed to the proxy inside an undo set (Edit > Undo), then
// the views render. Changes from elsewhere (Python, undo, state loading) refresh the rows.
#ifndef pqGaussianWidgetsPropertyWidget_h
#define pqGaussianWidgetsPropertyWidget_h

#include "pqMultichannelPropertyWidget.h"

#include <vtkNew.h>

#include <QList>

#include <array>
#include <vector>

class QLabel;
class QPushButton;
class QSpinBox;
class QVBoxLayout;
class pqDataRepresentation;
class pqGaussianWidgetRow;
class vtkEventQtSlotConnect;

class pqGaussianWidgetsPropertyWidget : public pqMultichannelPropertyWidget
{
  Q_OBJECT
  typedef pqMultichannelPropertyWidget Superclass;

public:
  pqGaussianWidgetsPropertyWidget(
    vtkSMProxy* proxy, vtkSMProperty* property, QWidget* parent = nullptr);
  ~pqGaussianWidgetsPropertyWidget() override;

private Q_SLOTS:
  /** The properties changed (this editor, Python, undo, a state file): show them. */
  void readProperties();
  /** The input's data or the coordinate array changed: new centre ranges. */
  void updateRanges();
  void onSelectionChanged(vtkSMProxy* representation, int index);

  void addWidget();
  void duplicateWidget();
  void removeWidget();
  void seedWidgets();
  /** Save... : the widgets and their model to a .mcvtf file (a file dialog). */
  void saveTransferFunction();
  /** Load... : a .mcvtf file onto this display, its model included (one undo step). */
  void loadTransferFunction();
  void endDrag();

private:
  typedef std::array<double, 8> Widget;

  /** Pushes the editor's widgets to the proxy as one undo step named `label`. */
  void writeProperties(const QString& label);
  void rebuildRows();
  void select(int index);
  void updateButtons();
  double step() const;
  /** Runs `call` (Python, `_display` bound to this display) through ParaView's Python
   * manager; returns multichannel_explorer._gui.text, the error it left ("" when none). */
  QString runOnDisplay(const QString& title, const QString& call);
  bool ownsRepresentation(vtkSMProxy* representation) const;
  pqDataRepresentation* representation() const;

  std::vector<Widget> Widgets; // values[7]: the opacity shown (a hidden one's remembered)
  std::vector<bool> Shown;
  std::vector<QString> Names; // GaussianWidgetNames, one per widget ("" unnamed)
  int Selected = -1;
  bool Writing = false;
  bool Dragging = false; // an opacity slider is pressed: its edits are one undo set
  bool Invalid = false; // GaussianWidgets is not a multiple of 8 long: not editable here
  int Dimensions = 3;
  double Ranges[3][2] = { { -1, 1 }, { -1, 1 }, { -1, 1 } };

  QList<pqGaussianWidgetRow*> Rows;
  QVBoxLayout* RowsLayout;
  QLabel* Message;
  QPushButton* AddButton;
  QPushButton* DuplicateButton;
  QPushButton* RemoveButton;
  QPushButton* SeedButton;
  QPushButton* SaveButton;
  QPushButton* LoadButton;
  QSpinBox* SeedCount;
  vtkNew<vtkEventQtSlotConnect> Connections;
};

#endif

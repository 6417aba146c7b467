#include "pqGaussianWidgetsPropertyWidget.h"

#include "pqGaussianWidgetRow.h"
#include "pqGaussianWidgetSelection.h"
#include "pqMultichannelPython.h"

#include "pqApplicationCore.h"
#include "pqCoreUtilities.h"
#include "pqDataRepresentation.h"
#include "pqFileDialog.h"
#include "pqPVApplicationCore.h"
#include "pqPythonManager.h"
#include "pqServerManagerModel.h"
#include "pqUndoStack.h"
#include "vtkCommand.h"
#include "vtkEventQtSlotConnect.h"
#include "vtkPVArrayInformation.h"
#include "vtkPVDataInformation.h"
#include "vtkPVDataSetAttributesInformation.h"
#include "vtkSMProperty.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMProxy.h"
#include "vtkSMSessionProxyManager.h"
#include "vtkSMTrace.h"
#include "vtkType.h"

#include "../../Filters/Core/transfer_function/GaussianWidgetFormula.h"

#include <QGridLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QFileInfo>
#include <QMessageBox>
#include <QPointer>
#include <QPushButton>
#include <QSpinBox>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <string>

namespace
{
const char* HiddenProperty = "GaussianWidgetsHidden";
const char* NamesProperty = "GaussianWidgetNames";

}

//-----------------------------------------------------------------------------
pqGaussianWidgetsPropertyWidget::pqGaussianWidgetsPropertyWidget(
  vtkSMProxy* smproxy, vtkSMProperty* smproperty, QWidget* parentWidget)
  : Superclass(smproxy, parentWidget)
{
  this->setObjectName("GaussianWidgetsEditor");
  this->setProperty(smproperty);
  this->setShowLabel(false);

  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->setSpacing(4);
  auto* title = new QLabel("<b>Gaussian Widgets</b>", this);
  layout->addWidget(title);
  this->Message = new QLabel(this);
  this->Message->setObjectName("message");
  this->Message->setWordWrap(true);
  this->Message->hide();
  layout->addWidget(this->Message);
  this->RowsLayout = new QVBoxLayout();
  this->RowsLayout->setSpacing(2);
  layout->addLayout(this->RowsLayout);

  // A button that runs `slot` when clicked.
  using Self = pqGaussianWidgetsPropertyWidget;
  auto newButton = [this](const char* name, const QString& text, const QString& tip,
                     void (Self::*slot)()) {
    auto* button = new QPushButton(text, this);
    button->setObjectName(name);
    button->setToolTip(tip);
    QObject::connect(button, &QPushButton::clicked, this, slot);
    return button;
  };
  this->AddButton =
    newButton("addWidget", "Add", "Add a widget at the centre of the domain", &Self::addWidget);
  this->DuplicateButton = newButton("duplicateWidget", "Duplicate",
    "Add a copy of the selected widget", &Self::duplicateWidget);
  this->RemoveButton =
    newButton("removeWidget", "Remove", "Remove the selected widget", &Self::removeWidget);
  this->SeedButton = newButton("seedWidgets", "Seed from clusters",
    "Replace the widgets by widgets at the k-means clusters of the reduced domain "
    "(multichannel_explorer.auto_widgets, as the toolbar's Seed Gaussian Widgets)",
    &Self::seedWidgets);
  this->SaveButton = newButton("saveTransferFunction", "Save...",
    "Save these widgets and the reduction model they live in to a transfer-function file "
    "(.mcvtf; the model beside it as .mcvmodel unless the reduction applies one)",
    &Self::saveTransferFunction);
  this->LoadButton = newButton("loadTransferFunction", "Load...",
    "Load a transfer-function file (.mcvtf): its reduction model becomes this display's "
    "reduction's ModelFile, then its widgets replace these (one undo step)",
    &Self::loadTransferFunction);
  this->SeedCount = new QSpinBox(this);
  this->SeedCount->setObjectName("seedCount");
  this->SeedCount->setRange(1, 64);
  this->SeedCount->setValue(4);
  this->SeedCount->setToolTip("How many widgets Seed from clusters makes");

  auto* buttons = new QGridLayout();
  buttons->addWidget(this->AddButton, 0, 0);
  buttons->addWidget(this->DuplicateButton, 0, 1);
  buttons->addWidget(this->RemoveButton, 0, 2);
  buttons->addWidget(this->SeedButton, 1, 0, 1, 2);
  buttons->addWidget(this->SeedCount, 1, 2);
  buttons->addWidget(this->SaveButton, 2, 0);
  buttons->addWidget(this->LoadButton, 2, 1);
  layout->addLayout(buttons);

  // Any change of the properties, whoever made it, is shown.
  this->Connections->Connect(
    smproperty, vtkCommand::ModifiedEvent, this, SLOT(readProperties()));
  if (vtkSMProperty* hidden = smproxy->GetProperty(HiddenProperty))
  {
    this->Connections->Connect(hidden, vtkCommand::ModifiedEvent, this, SLOT(readProperties()));
  }
  if (vtkSMProperty* names = smproxy->GetProperty(NamesProperty))
  {
    this->Connections->Connect(names, vtkCommand::ModifiedEvent, this, SLOT(readProperties()));
  }
  if (vtkSMProperty* coordinates = smproxy->GetProperty("CoordinateArray"))
  {
    this->Connections->Connect(
      coordinates, vtkCommand::ModifiedEvent, this, SLOT(updateRanges()));
  }
  if (pqDataRepresentation* repr = this->representation())
  {
    QObject::connect(repr, &pqDataRepresentation::dataUpdated, this,
      &pqGaussianWidgetsPropertyWidget::updateRanges);
  }
  pqGaussianWidgetSelection* selection = pqGaussianWidgetSelection::instance();
  QObject::connect(selection, &pqGaussianWidgetSelection::selectionChanged, this,
    &pqGaussianWidgetsPropertyWidget::onSelectionChanged);

  this->updateRanges();
  this->readProperties();
  if (this->ownsRepresentation(selection->representation()))
  {
    this->onSelectionChanged(selection->representation(), selection->index());
  }
}

//-----------------------------------------------------------------------------
pqGaussianWidgetsPropertyWidget::~pqGaussianWidgetsPropertyWidget()
{
  this->endDrag();
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetsPropertyWidget::endDrag()
{
  // Closes the undo set a slider press opened, whatever ends the drag.
  if (this->Dragging)
  {
    this->Dragging = false;
    END_UNDO_SET();
  }
}

//-----------------------------------------------------------------------------
pqDataRepresentation* pqGaussianWidgetsPropertyWidget::representation() const
{
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  return model->findItem<pqDataRepresentation*>(this->proxy());
}

//-----------------------------------------------------------------------------
bool pqGaussianWidgetsPropertyWidget::ownsRepresentation(vtkSMProxy* representation) const
{
  // The handles may name the display (what this editor edits) or its Gaussian TF
  // sub-representation, which owns the property.
  return representation &&
    (representation == this->proxy() || representation == this->property()->GetParent());
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetsPropertyWidget::readProperties()
{
  if (this->Writing)
  {
    return;
  }
  vtkSMPropertyHelper flatHelper(this->property());
  const std::vector<double> flat = flatHelper.GetArray<double>();
  std::vector<double> hidden;
  if (vtkSMProperty* hiddenProperty = this->proxy()->GetProperty(HiddenProperty))
  {
    hidden = vtkSMPropertyHelper(hiddenProperty).GetArray<double>();
  }

  this->Invalid = flat.size() % 8 != 0;
  this->Message->setVisible(this->Invalid);
  if (this->Invalid)
  {
    this->Message->setText(QString("GaussianWidgets holds %1 numbers, not 8 per widget: "
                                   "correct it from Python to edit it here.")
                             .arg(flat.size()));
  }
  const size_t count = this->Invalid ? 0 : flat.size() / 8;
  // A hidden-list that does not match (a script changed the widgets) is ignored, and so
  // is the mark of a widget a script gave an opacity again.
  const bool hiddenMatches = hidden.size() == count;
  this->Names.assign(count, QString());
  if (vtkSMProperty* namesProperty = this->proxy()->GetProperty(NamesProperty))
  {
    vtkSMPropertyHelper names(namesProperty);
    for (unsigned int i = 0; i < names.GetNumberOfElements() && i < count; ++i)
    {
      this->Names[i] = QString::fromUtf8(names.GetAsString(i));
    }
  }
  const size_t before = this->Widgets.size();
  this->Widgets.resize(count);
  this->Shown.assign(count, true);
  for (size_t i = 0; i < count; ++i)
  {
    std::copy(flat.begin() + 8 * i, flat.begin() + 8 * i + 8, this->Widgets[i].begin());
    if (hiddenMatches && hidden[i] >= 0 && this->Widgets[i][7] == 0)
    {
      this->Shown[i] = false;
      this->Widgets[i][7] = hidden[i];
    }
  }
  if (count != before || this->Rows.size() != static_cast<int>(count))
  {
    this->rebuildRows();
  }
  else
  {
    for (size_t i = 0; i < count; ++i)
    {
      this->Rows[static_cast<int>(i)]->setValues(this->Widgets[i].data(), this->Shown[i]);
      this->Rows[static_cast<int>(i)]->setName(this->Names[i]);
    }
  }
  if (this->Selected >= static_cast<int>(count))
  {
    this->select(static_cast<int>(count) - 1);
  }
  this->updateButtons();
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetsPropertyWidget::writeProperties(const QString& label)
{
  std::vector<double> flat;
  std::vector<double> hidden;
  bool anyHidden = false;
  for (size_t i = 0; i < this->Widgets.size(); ++i)
  {
    Widget w = this->Widgets[i];
    hidden.push_back(this->Shown[i] ? -1.0 : w[7]);
    anyHidden = anyHidden || !this->Shown[i];
    if (!this->Shown[i])
    {
      w[7] = 0.0;
    }
    flat.insert(flat.end(), w.begin(), w.end());
  }
  if (!anyHidden)
  {
    hidden.clear(); // every widget shown: nothing to remember
  }

  this->Writing = true;
  {
    SCOPED_UNDO_SET(label);
    SM_SCOPED_TRACE(PropertiesModified).arg("proxy", this->proxy());
    // The hidden list first: whoever watches GaussianWidgets sees both current.
    if (vtkSMProperty* hiddenProperty = this->proxy()->GetProperty(HiddenProperty))
    {
      vtkSMPropertyHelper(hiddenProperty)
        .Set(hidden.data(), static_cast<unsigned int>(hidden.size()));
    }
    if (vtkSMProperty* namesProperty = this->proxy()->GetProperty(NamesProperty))
    {
      // Kept one per widget while any has a name (an empty list: none named).
      this->Names.resize(this->Widgets.size());
      const bool anyNamed = std::any_of(
        this->Names.begin(), this->Names.end(), [](const QString& n) { return !n.isEmpty(); });
      vtkSMPropertyHelper names(namesProperty);
      names.SetNumberOfElements(anyNamed ? static_cast<unsigned int>(this->Names.size()) : 0);
      for (size_t i = 0; anyNamed && i < this->Names.size(); ++i)
      {
        names.Set(static_cast<unsigned int>(i), this->Names[i].toUtf8().constData());
      }
    }
    vtkSMPropertyHelper(this->property()).Set(flat.data(), static_cast<unsigned int>(flat.size()));
    this->proxy()->UpdateVTKObjects();
  }
  this->Writing = false;
  if (pqDataRepresentation* repr = this->representation())
  {
    repr->renderViewEventually();
  }
  this->updateButtons();
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetsPropertyWidget::rebuildRows()
{
  for (pqGaussianWidgetRow* row : this->Rows)
  {
    delete row;
  }
  this->Rows.clear();
  this->endDrag(); // its slider is gone
  const double step = this->step();
  for (size_t i = 0; i < this->Widgets.size(); ++i)
  {
    auto* row = new pqGaussianWidgetRow(static_cast<int>(i), this);
    row->setCentreRanges(this->Ranges, this->Dimensions, step);
    row->setValues(this->Widgets[i].data(), this->Shown[i]);
    row->setName(i < this->Names.size() ? this->Names[i] : QString());
    row->setHighlighted(static_cast<int>(i) == this->Selected);
    this->RowsLayout->addWidget(row);
    this->Rows.append(row);

    QObject::connect(row, &pqGaussianWidgetRow::activated, this,
      [this](int index) { this->select(index); });
    QObject::connect(
      row, &pqGaussianWidgetRow::valueEdited, this, [this](int index, int field, double value) {
        this->Widgets[index][field] = value;
        this->select(index);
        this->writeProperties(
          field == pqGaussianWidgetRow::OPACITY ? "Gaussian Widget Opacity"
            : field == pqGaussianWidgetRow::SIGMA ? "Gaussian Widget Sigma"
                                                   : "Move Gaussian Widget");
      });
    QObject::connect(row, &pqGaussianWidgetRow::colourEdited, this,
      [this](int index, double r, double g, double b) {
        this->Widgets[index][4] = r;
        this->Widgets[index][5] = g;
        this->Widgets[index][6] = b;
        this->select(index);
        this->writeProperties("Gaussian Widget Colour");
      });
    QObject::connect(
      row, &pqGaussianWidgetRow::nameEdited, this, [this](int index, const QString& name) {
        this->Names.resize(this->Widgets.size());
        this->Names[index] = name;
        this->select(index);
        this->writeProperties("Rename Gaussian Widget");
      });
    QObject::connect(row, &pqGaussianWidgetRow::visibilityEdited, this, [this](int index, bool on) {
      this->Shown[index] = on;
      this->select(index);
      this->writeProperties(on ? "Show Gaussian Widget" : "Hide Gaussian Widget");
    });
    // A slider drag renders live but is one undo step (undo sets nest).
    QObject::connect(row, &pqGaussianWidgetRow::dragStarted, this, [this]() {
      if (!this->Dragging)
      {
        this->Dragging = true;
        BEGIN_UNDO_SET("Gaussian Widget Opacity");
      }
    });
    QObject::connect(
      row, &pqGaussianWidgetRow::dragFinished, this, &pqGaussianWidgetsPropertyWidget::endDrag);
  }
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetsPropertyWidget::updateRanges()
{
  // The centre spin boxes span the bounds of the coordinate array on the input.
  pqDataRepresentation* repr = this->representation();
  vtkPVDataInformation* info = repr ? repr->getInputDataInformation() : nullptr;
  const char* name = this->proxy()->GetProperty("CoordinateArray")
    ? vtkSMPropertyHelper(this->proxy(), "CoordinateArray").GetAsString()
    : nullptr;
  vtkPVArrayInformation* array = (info && name)
    ? info->GetPointDataInformation()->GetArrayInformation(name)
    : nullptr;
  if (!array || array->GetNumberOfComponents() < 2)
  {
    return; // keep the last ranges
  }
  int dimensions = std::min(3, array->GetNumberOfComponents());
  if (array->GetDataType() == VTK_UNSIGNED_SHORT)
  {
    // float16 coordinates (DimensionReduction's CoordinatePrecision Float16): the array's
    // range is that of the bits; the decoded one comes as the field array <name>Range.
    array = info->GetFieldDataInformation()->GetArrayInformation((std::string(name) + "Range").c_str());
    if (!array || array->GetNumberOfComponents() < dimensions)
    {
      return; // keep the last ranges
    }
  }
  double ranges[3][2] = { { 0, 0 }, { 0, 0 }, { 0, 0 } };
  for (int axis = 0; axis < dimensions; ++axis)
  {
    array->GetComponentRange(axis, ranges[axis]);
  }
  // Data updates come with renders (every edit): only a real change touches the rows,
  // which are then kept (a slider being dragged must survive).
  if (dimensions == this->Dimensions && std::equal(&ranges[0][0], &ranges[0][0] + 6,
                                           &this->Ranges[0][0]))
  {
    return;
  }
  this->Dimensions = dimensions;
  std::copy(&ranges[0][0], &ranges[0][0] + 6, &this->Ranges[0][0]);
  for (pqGaussianWidgetRow* row : this->Rows)
  {
    row->setCentreRanges(this->Ranges, this->Dimensions, this->step());
  }
}

//-----------------------------------------------------------------------------
double pqGaussianWidgetsPropertyWidget::step() const
{
  // A hundredth of the domain's extent.
  const double span = std::max({ this->Ranges[0][1] - this->Ranges[0][0],
    this->Ranges[1][1] - this->Ranges[1][0], this->Ranges[2][1] - this->Ranges[2][0] });
  return span > 0 ? span / 100.0 : 0.01;
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetsPropertyWidget::select(int index)
{
  if (index != this->Selected)
  {
    this->Selected = index;
    for (int i = 0; i < this->Rows.size(); ++i)
    {
      this->Rows[i]->setHighlighted(i == index);
    }
    this->updateButtons();
  }
  pqGaussianWidgetSelection::instance()->select(this->proxy(), index);
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetsPropertyWidget::onSelectionChanged(vtkSMProxy* representation, int index)
{
  // Another part (a handle in the domain view) selected a widget: highlight its row.
  const int selected =
    this->ownsRepresentation(representation) && index < static_cast<int>(this->Widgets.size())
    ? index
    : -1;
  if (selected == this->Selected)
  {
    return;
  }
  this->Selected = selected;
  for (int i = 0; i < this->Rows.size(); ++i)
  {
    this->Rows[i]->setHighlighted(i == selected);
  }
  this->updateButtons();
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetsPropertyWidget::updateButtons()
{
  const bool selected = this->Selected >= 0 && !this->Invalid;
  this->AddButton->setEnabled(!this->Invalid);
  this->DuplicateButton->setEnabled(selected);
  this->RemoveButton->setEnabled(selected);
  this->SaveButton->setEnabled(!this->Invalid);
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetsPropertyWidget::addWidget()
{
  // At the centre of the domain, a tenth of its extent wide, the next palette colour.
  Widget w;
  double span = 0.0;
  for (int axis = 0; axis < 3; ++axis)
  {
    w[axis] = axis < this->Dimensions ? 0.5 * (this->Ranges[axis][0] + this->Ranges[axis][1])
                                      : 0.0;
    span = std::max(span, this->Ranges[axis][1] - this->Ranges[axis][0]);
  }
  w[3] = span > 0 ? span / 10.0 : 1.0;
  // The next colour of the suite's palette (ColorBrewer Set1, as auto_widgets seeds them).
  const unsigned char* colour = mcv::kWidgetPalette[this->Widgets.size() % mcv::kWidgetPaletteSize];
  for (int c = 0; c < 3; ++c)
  {
    w[4 + c] = colour[c] / 255.0;
  }
  w[7] = 0.5;
  this->Widgets.push_back(w);
  this->Shown.push_back(true);
  this->Names.resize(this->Widgets.size());
  this->rebuildRows();
  this->writeProperties("Add Gaussian Widget");
  this->select(static_cast<int>(this->Widgets.size()) - 1);
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetsPropertyWidget::duplicateWidget()
{
  if (this->Selected < 0 || this->Selected >= static_cast<int>(this->Widgets.size()))
  {
    return;
  }
  this->Widgets.push_back(this->Widgets[this->Selected]);
  this->Shown.push_back(this->Shown[this->Selected]);
  this->Names.resize(this->Widgets.size() - 1);
  this->Names.push_back(this->Names[this->Selected]);
  this->rebuildRows();
  this->writeProperties("Duplicate Gaussian Widget");
  this->select(static_cast<int>(this->Widgets.size()) - 1);
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetsPropertyWidget::removeWidget()
{
  const int index = this->Selected;
  if (index < 0 || index >= static_cast<int>(this->Widgets.size()))
  {
    return;
  }
  this->Widgets.erase(this->Widgets.begin() + index);
  this->Shown.erase(this->Shown.begin() + index);
  this->Names.resize(this->Widgets.size() + 1);
  this->Names.erase(this->Names.begin() + index);
  this->Selected = -1;
  this->rebuildRows();
  this->writeProperties("Remove Gaussian Widget");
  this->select(std::min(index, static_cast<int>(this->Widgets.size()) - 1));
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetsPropertyWidget::seedWidgets()
{
  // The same helper as the toolbar's Seed Gaussian Widgets, on this display; its
  // widgets replace these (one undo step; errors go to the Output Messages).
  pqPythonManager* python =
    pqPVApplicationCore::instance() ? pqPVApplicationCore::instance()->pythonManager() : nullptr;
  vtkSMSessionProxyManager* pxm = this->proxy()->GetSessionProxyManager();
  const char* name = pxm ? pxm->GetProxyName("representations", this->proxy()) : nullptr;
  if (!python || !name)
  {
    QMessageBox::warning(pqCoreUtilities::mainWidget(), "Seed from clusters",
      "Seeding needs ParaView's Python support and a registered display.");
    return;
  }
  const QString code =
    QString("from paraview import servermanager as _sm\n"
            "import multichannel_explorer as _mce\n"
            "_display = _sm._getPyProxy(_sm.ProxyManager().SMProxyManager.GetProxy("
            "'representations', '%1'))\n"
            "_mce.auto_widgets(_display, %2)\n"
            "del _display\n")
      .arg(QString(name).replace('\'', "\\'"))
      .arg(this->SeedCount->value());
  // The helper creates a ReducedDomain filter and restores the active source: the
  // Properties panel may rebuild its display section, deleting this editor meanwhile.
  // Nothing of `this` is used after the call.
  QPointer<pqDataRepresentation> repr = this->representation();
  {
    SCOPED_UNDO_SET("Seed Gaussian Widgets");
    python->executeCode(code.toUtf8());
  }
  if (repr)
  {
    repr->renderViewEventually();
  }
}

//-----------------------------------------------------------------------------
QString pqGaussianWidgetsPropertyWidget::runOnDisplay(const QString& title, const QString& call)
{
  pqPythonManager* python =
    pqPVApplicationCore::instance() ? pqPVApplicationCore::instance()->pythonManager() : nullptr;
  vtkSMSessionProxyManager* pxm = this->proxy()->GetSessionProxyManager();
  const char* name = pxm ? pxm->GetProxyName("representations", this->proxy()) : nullptr;
  if (!python || !name)
  {
    return QString("%1 needs ParaView's Python support and a registered display.").arg(title);
  }
  const QString code = QString("import multichannel_explorer as _mce\n"
                               "import multichannel_explorer._gui as _g\n"
                               "_g.text = 'the Python call did not finish'\n"
                               "_g.on_display('%1', lambda _display: %2)\n")
                         .arg(QString(name).replace('\\', "\\\\").replace('\'', "\\'"), call);
  python->executeCode(code.toUtf8());
  return pqMultichannelPython::text("multichannel_explorer._gui", "text");
}

namespace
{
// A file name as a Python string literal (repr-safe: backslashes and quotes escaped).
QString pythonString(const QString& text)
{
  QString escaped = text;
  escaped.replace('\\', "\\\\").replace('\'', "\\'");
  return "'" + escaped + "'";
}

// A transfer function file (.mcvtf) of the client's file system (the Python helper reads
// and writes it where it runs), chosen in a dialog; empty when cancelled.
QString chooseTransferFunctionFile(
  const char* title, const char* objectName, pqFileDialog::FileMode mode)
{
  pqFileDialog dialog(
    nullptr, pqCoreUtilities::mainWidget(), title, QString(), "Transfer functions (*.mcvtf)");
  dialog.setObjectName(objectName);
  dialog.setFileMode(mode);
  if (dialog.exec() != QDialog::Accepted || dialog.getSelectedFiles().isEmpty())
  {
    return QString();
  }
  return dialog.getSelectedFiles().first();
}
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetsPropertyWidget::saveTransferFunction()
{
  QString path = chooseTransferFunctionFile(
    "Save Transfer Function", "SaveTransferFunctionDialog", pqFileDialog::AnyFile);
  if (path.isEmpty())
  {
    return;
  }
  if (!path.endsWith(".mcvtf"))
  {
    path += ".mcvtf";
  }
  const QString error = this->runOnDisplay("Save Transfer Function",
    QString("_mce.save_transfer_function(_display, %1)").arg(pythonString(path)));
  if (!error.isEmpty())
  {
    QMessageBox::warning(pqCoreUtilities::mainWidget(), "Save Transfer Function", error);
  }
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetsPropertyWidget::loadTransferFunction()
{
  const QString path = chooseTransferFunctionFile(
    "Load Transfer Function", "LoadTransferFunctionDialog", pqFileDialog::ExistingFile);
  if (path.isEmpty())
  {
    return;
  }
  // The reduction's ModelFile and the widgets change together: one undo step. On an error
  // the helper changes nothing, and an empty undo set is not pushed.
  QPointer<pqDataRepresentation> repr = this->representation();
  QString error;
  {
    SCOPED_UNDO_SET("Load Transfer Function");
    error = this->runOnDisplay("Load Transfer Function",
      QString("_mce.load_transfer_function(_display, %1)").arg(pythonString(path)));
  }
  if (!error.isEmpty())
  {
    QMessageBox::warning(pqCoreUtilities::mainWidget(), "Load Transfer Function", error);
  }
  else if (repr)
  {
    repr->renderViewEventually();
  }
}

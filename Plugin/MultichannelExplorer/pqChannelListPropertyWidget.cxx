#include "pqChannelListPropertyWidget.h"

#include "vtkCommand.h"
#include "vtkEventQtSlotConnect.h"
#include "vtkPVArrayInformation.h"
#include "vtkPVDataInformation.h"
#include "vtkPVDataSetAttributesInformation.h"
#include "vtkSMArrayListDomain.h"
#include "vtkSMInputProperty.h"
#include "vtkSMProperty.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMSourceProxy.h"
#include "vtkSMUncheckedPropertyHelper.h"

#include <QHeaderView>
#include <QLabel>
#include <QSet>
#include <QTreeWidget>
#include <QVBoxLayout>

#include <algorithm>
#include <string>
#include <vector>

namespace
{
// The label table of a channel travels as the field array "<channel>_labels".
const char* LabelSuffix = "_labels";
}

//-----------------------------------------------------------------------------
pqChannelListPropertyWidget::pqChannelListPropertyWidget(
  vtkSMProxy* smproxy, vtkSMProperty* smproperty, QWidget* parentObject)
  : Superclass(smproxy, smproperty, parentObject, nullptr, true)
{
  this->setChangeAvailableAsChangeFinished(true);

  this->Summary = this->addMessageLabel("channelSummary");
  this->panelLayout()->setSpacing(2);
  this->Tree = new QTreeWidget(this);
  this->Tree->setObjectName("channelList");
  this->Tree->setColumnCount(2);
  this->Tree->setHeaderLabels({ "Channel", "Values" });
  this->Tree->setRootIsDecorated(false);
  this->Tree->setUniformRowHeights(true);
  this->Tree->header()->setStretchLastSection(true);
  this->Tree->setToolTip("The channels of the input, numbered in the order the filter takes "
                         "them. Ticked: used. None ticked: every channel is used.");
  this->panelLayout()->addWidget(this->Tree);

  QObject::connect(this->Tree, &QTreeWidget::itemChanged, this, [this]() {
    if (!this->Updating)
    {
      this->updateSummary();
      Q_EMIT this->channelsChanged();
    }
  });
  if (auto* domain = smproperty->FindDomain<vtkSMArrayListDomain>())
  {
    this->Connections->Connect(domain, vtkCommand::DomainModifiedEvent, this, SLOT(rebuild()));
  }
  this->rebuild();
  this->addPropertyLink(this, "channels", SIGNAL(channelsChanged()), smproperty);
  // The domain fills the property after it changed (vtkSMChannelArrayListDomain): the
  // ticks follow the property whoever sets it.
  this->Connections->Connect(smproperty, vtkCommand::ModifiedEvent, this, SLOT(readTicks()));
  this->Connections->Connect(
    smproperty, vtkCommand::UncheckedPropertyModifiedEvent, this, SLOT(readTicks()));
}

//-----------------------------------------------------------------------------
QList<QVariant> pqChannelListPropertyWidget::propertyValues() const
{
  QList<QVariant> values;
  vtkSMUncheckedPropertyHelper helper(this->property());
  for (unsigned int i = 0; i < helper.GetNumberOfElements(); ++i)
  {
    values.append(QString::fromUtf8(helper.GetAsString(i)));
  }
  return values;
}

//-----------------------------------------------------------------------------
void pqChannelListPropertyWidget::readTicks()
{
  if (!this->Updating)
  {
    this->setChannels(this->propertyValues());
  }
}

//-----------------------------------------------------------------------------
pqChannelListPropertyWidget::~pqChannelListPropertyWidget() = default;

//-----------------------------------------------------------------------------
void pqChannelListPropertyWidget::rebuild()
{
  auto* domain = this->property()->FindDomain<vtkSMArrayListDomain>();
  // The ticks: the property's values as the panel holds them (unchecked: not applied yet).
  QSet<QString> keep;
  for (const QVariant& v : this->propertyValues())
  {
    keep.insert(v.toString());
  }

  // The input's data information: type, components, range and label tables.
  vtkPVDataInformation* info = nullptr;
  vtkSMUncheckedPropertyHelper input(this->proxy(), "Input", /*quiet*/ true);
  if (auto* source = vtkSMSourceProxy::SafeDownCast(input.GetAsProxy()))
  {
    info = source->GetDataInformation(input.GetOutputPort());
  }

  // The channels in the domain's order: the order the property is filled in and the
  // filters take them in (the feature vector's layout), which the numbers show.
  std::vector<std::string> order;
  for (unsigned int i = 0; domain && i < domain->GetNumberOfStrings(); ++i)
  {
    order.emplace_back(domain->GetString(i));
  }

  this->Updating = true;
  this->Tree->clear();
  for (unsigned int i = 0; i < order.size(); ++i)
  {
    const QString name = QString::fromUtf8(order[i].c_str());
    auto* item = new QTreeWidgetItem(this->Tree);
    item->setText(0, QString("#%1  %2").arg(i + 1).arg(name));
    item->setData(0, Qt::UserRole, name);
    item->setFlags(item->flags() | Qt::ItemIsUserCheckable);
    item->setCheckState(0, keep.contains(name) ? Qt::Checked : Qt::Unchecked);
    QString values;
    vtkPVArrayInformation* array = info && info->GetPointDataInformation()
      ? info->GetPointDataInformation()->GetArrayInformation(name.toUtf8().constData())
      : nullptr;
    if (array)
    {
      double range[2];
      array->GetComponentRange(-1, range);
      values = QString("%1%2, %3..%4")
                 .arg(array->GetDataTypeAsString())
                 .arg(array->GetNumberOfComponents() > 1
                     ? QString(" x %1").arg(array->GetNumberOfComponents())
                     : QString())
                 .arg(range[0], 0, 'g', 4)
                 .arg(range[1], 0, 'g', 4);
    }
    const QString table = name + LabelSuffix;
    if (info && info->GetFieldDataInformation() &&
      info->GetFieldDataInformation()->GetArrayInformation(table.toUtf8().constData()))
    {
      values += values.isEmpty() ? "atlas: named labels" : "; atlas: named labels";
    }
    item->setText(1, values);
    item->setToolTip(0, QString("Channel %1 of the input: point array '%2'").arg(i + 1).arg(name));
  }
  this->Tree->resizeColumnToContents(0);
  // Tall enough for every channel up to 8 rows; a scroll bar beyond.
  const int rows = std::min(8, std::max(1, this->Tree->topLevelItemCount()));
  const int rowHeight = this->Tree->sizeHintForRow(0) > 0 ? this->Tree->sizeHintForRow(0) : 20;
  this->Tree->setFixedHeight(this->Tree->header()->sizeHint().height() + rows * rowHeight + 6);
  this->Updating = false;
  this->updateSummary();
}

//-----------------------------------------------------------------------------
QList<QVariant> pqChannelListPropertyWidget::channels() const
{
  QList<QVariant> names;
  for (int i = 0; i < this->Tree->topLevelItemCount(); ++i)
  {
    QTreeWidgetItem* item = this->Tree->topLevelItem(i);
    if (item->checkState(0) == Qt::Checked)
    {
      names.append(item->data(0, Qt::UserRole));
    }
  }
  return names;
}

//-----------------------------------------------------------------------------
void pqChannelListPropertyWidget::setChannels(const QList<QVariant>& names)
{
  QSet<QString> ticked;
  for (const QVariant& v : names)
  {
    ticked.insert(v.toString());
  }
  this->Updating = true;
  for (int i = 0; i < this->Tree->topLevelItemCount(); ++i)
  {
    QTreeWidgetItem* item = this->Tree->topLevelItem(i);
    item->setCheckState(
      0, ticked.contains(item->data(0, Qt::UserRole).toString()) ? Qt::Checked : Qt::Unchecked);
  }
  this->Updating = false;
  this->updateSummary();
}

//-----------------------------------------------------------------------------
QString pqChannelListPropertyWidget::summary() const
{
  return this->Summary->text();
}

//-----------------------------------------------------------------------------
void pqChannelListPropertyWidget::updateSummary()
{
  const int total = this->Tree->topLevelItemCount();
  const int used = this->channels().size();
  QStringList numbers;
  for (int i = 0; i < total; ++i)
  {
    if (used == 0 || this->Tree->topLevelItem(i)->checkState(0) == Qt::Checked)
    {
      numbers << QString("#%1").arg(i + 1);
    }
  }
  if (total == 0)
  {
    this->Summary->setText("No channels yet: apply the input first.");
  }
  else if (used == 0)
  {
    this->Summary->setText(QString("None ticked: all %1 channels used (%2)")
                             .arg(total)
                             .arg(numbers.join(", ")));
  }
  else
  {
    this->Summary->setText(QString("%1 of %2 channel%3 used: %4")
                             .arg(used)
                             .arg(total)
                             .arg(total == 1 ? "" : "s")
                             .arg(numbers.join(", ")));
  }
}

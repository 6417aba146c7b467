// The Channels list of the suite's filters (panel_widget="channel_list" on MultichannelFeatures',
// DimensionReduction's and BestViewpoint's Channels): one row per channel of the input, as
// vtkSMChannelArrayListDomain offers them (channels only: no Features, Foreground,
// ReducedCoordinates, ghost or validity arrays), each numbered in the order the filters take
// them, the domain's (ParaView lists arrays by name: "#1 aal", "#2 brodmann", "#3 ch2"),
// with its type, components and range, and "atlas: named
// labels" for a channel that carries a label table (mcvLabelTables.h). A check box per row
// says whether the channel is used; the line above the list says how many are ("2 of 3
// channels used", or "all 3 used" when none is ticked, which the filters read as every
// channel). The property holds the ticked names, in the list's order.
#ifndef pqChannelListPropertyWidget_h
#define pqChannelListPropertyWidget_h

#include "pqMultichannelPropertyWidget.h"

#include <QList>
#include <QVariant>
#include <vtkNew.h>

class QLabel;
class QTreeWidget;
class vtkEventQtSlotConnect;

class pqChannelListPropertyWidget : public pqMultichannelPropertyWidget
{
  Q_OBJECT
  typedef pqMultichannelPropertyWidget Superclass;
  Q_PROPERTY(QList<QVariant> channels READ channels WRITE setChannels NOTIFY channelsChanged)

public:
  pqChannelListPropertyWidget(vtkSMProxy* proxy, vtkSMProperty* property, QWidget* parent = nullptr);
  ~pqChannelListPropertyWidget() override;

  /** The ticked channels' names, in the list's order. */
  QList<QVariant> channels() const;
  void setChannels(const QList<QVariant>& names);

  /** The line above the list, e.g. "2 of 3 channels used". */
  QString summary() const;

Q_SIGNALS:
  void channelsChanged();

private Q_SLOTS:
  /** The domain (the input's arrays) changed: rebuild the rows, keeping the ticks. */
  void rebuild();
  void updateSummary();
  /** The property changed (the domain filled it, a script, undo): show its values. */
  void readTicks();

private:
  QList<QVariant> propertyValues() const;

  QTreeWidget* Tree;
  QLabel* Summary;
  bool Updating = false;
  vtkNew<vtkEventQtSlotConnect> Connections;
};

#endif

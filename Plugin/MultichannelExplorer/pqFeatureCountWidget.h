// The Properties-panel line that says how many features the current settings give on the
// current input (panel_widget="feature_count" of MultichannelFeatures' and
// DimensionReduction's FeatureCount): "130 features: 65 channels x 2 per channel
// (intensity, gradient magnitude)". The presets are named 6D and 24D after the 3-channel
// case; the feature vector has (channels x features per channel) numbers, so this line
// shows what a preset means on the volume at hand, before Apply, and follows every change
// of Channels, FeatureSet, the Custom toggles and the input's arrays.
//
// The count is the filters' own rule (mcv::featureCount): 2 per channel for 6D, 8 for
// 24D, the ticked features for Custom (the gradient counts 3); every component of every
// selected array is a channel, no selection meaning every numeric point array but the
// suite's outputs and ParaView's bookkeeping arrays. DimensionReduction's "Use input
// array" and "Automatic" with a Features array take that array's components. After a run
// the filters' information property NumberOfFeatures (NumberOfFeaturesUsed) has the count
// that was used.
#ifndef pqFeatureCountWidget_h
#define pqFeatureCountWidget_h

#include "pqMultichannelPropertyWidget.h"

#include <vtkNew.h>

class QLabel;
class vtkEventQtSlotConnect;

class pqFeatureCountWidget : public pqMultichannelPropertyWidget
{
  Q_OBJECT
  typedef pqMultichannelPropertyWidget Superclass;

public:
  pqFeatureCountWidget(vtkSMProxy* proxy, vtkSMProperty* property, QWidget* parent = nullptr);
  ~pqFeatureCountWidget() override;

  /** The line shown, e.g. "130 features: 65 channels x 2 per channel (...)". */
  QString text() const;

private Q_SLOTS:
  void updateCount();
  /** The input changed: follow its data updates. */
  void watchInput();

private:
  QLabel* Label;
  vtkNew<vtkEventQtSlotConnect> Connections;
};

#endif

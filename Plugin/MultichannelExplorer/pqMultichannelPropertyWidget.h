// The base of the plugin's Properties-panel widgets (the channel list, the feature count,
// the Gaussian widgets editor).
#ifndef pqMultichannelPropertyWidget_h
#define pqMultichannelPropertyWidget_h

#include "pqPropertyWidget.h"

class QLabel;
class QVBoxLayout;

/**
 * A pqPropertyWidget bound to its property, named `objectName` when given (the GUI tests
 * find it by it), with the panel's label beside it or not (`showLabel`: without, the widget
 * says itself what it is), its content in a vertical layout without margins, so that it
 * lines up with the panel's other lines.
 */
class pqMultichannelPropertyWidget : public pqPropertyWidget
{
  Q_OBJECT
  typedef pqPropertyWidget Superclass;

public:
  pqMultichannelPropertyWidget(vtkSMProxy* proxy, vtkSMProperty* property, QWidget* parent,
    const char* objectName, bool showLabel);
  ~pqMultichannelPropertyWidget() override = default;

protected:
  /** The vertical layout that holds the widget's content. */
  QVBoxLayout* panelLayout() const { return this->PanelLayout; }
  /** A word-wrapped label named `objectName`, added to the layout. */
  QLabel* addMessageLabel(const char* objectName);

private:
  Q_DISABLE_COPY(pqMultichannelPropertyWidget)
  QVBoxLayout* PanelLayout;
};

#endif

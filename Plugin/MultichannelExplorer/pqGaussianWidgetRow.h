// One Gaussian widget in the editor of a "Gaussian TF Volume" display
// (pqGaussianWidgetsPropertyWidget): visibility, colour, name, peak opacity, sigma and
// centre.
// The row only shows values and reports the user's edits; the editor owns the values
// (a spin box rounds to its decimals, so values are never read back from the widgets).
#ifndef pqGaussianWidgetRow_h
#define pqGaussianWidgetRow_h

#include <QFrame>

class QCheckBox;
class QDoubleSpinBox;
class QLabel;
class QLineEdit;
class QSlider;
class pqColorChooserButton;

class pqGaussianWidgetRow : public QFrame
{
  Q_OBJECT
  typedef QFrame Superclass;

public:
  /** Positions in a widget's 8 numbers (cx, cy, cz, sigma, r, g, b, opacity). */
  enum Field
  {
    CX = 0,
    CY = 1,
    CZ = 2,
    SIGMA = 3,
    OPACITY = 7
  };

  pqGaussianWidgetRow(int index, QWidget* parent = nullptr);

  /** Shows `values` (8 numbers; values[7] is the opacity shown on the slider, the one a
   * hidden widget gets back) without emitting edits. */
  void setValues(const double values[8], bool visible);

  /** Shows the widget's name (GaussianWidgetNames; "" shows "Widget N" greyed). */
  void setName(const QString& name);

  /** Centre spin box ranges per axis; the third axis is disabled for 2D coordinates.
   * `step` is the spin boxes' step (and sets their decimals). */
  void setCentreRanges(const double ranges[3][2], int dimensions, double step);

  void setHighlighted(bool highlighted);

Q_SIGNALS:
  /** The user changed field `field` (CX, CY, CZ, SIGMA or OPACITY) of this row. */
  void valueEdited(int index, int field, double value);
  void colourEdited(int index, double r, double g, double b);
  void visibilityEdited(int index, bool visible);
  /** The user renamed the widget (Enter or leaving the field). */
  void nameEdited(int index, const QString& name);
  /** The user pressed or released the opacity slider (a drag is one undo step). */
  void dragStarted(int index);
  void dragFinished(int index);
  /** The user clicked the row or one of its widgets. */
  void activated(int index);

protected:
  void mousePressEvent(QMouseEvent* event) override;
  bool eventFilter(QObject* watched, QEvent* event) override;

private:
  QDoubleSpinBox* newSpinBox(const QString& name);
  void showOpacity(double opacity);

  int Index;
  bool Updating = false;
  QCheckBox* Visible;
  QLineEdit* Name;
  pqColorChooserButton* Colour;
  QSlider* Opacity;
  QLabel* OpacityValue;
  QDoubleSpinBox* Sigma;
  QDoubleSpinBox* Centre[3];
};

#endif

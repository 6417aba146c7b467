#include "pqGaussianWidgetRow.h"

#include "pqColorChooserButton.h"

#include <QCheckBox>
#include <QColor>
#include <QDoubleSpinBox>
#include <QEvent>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QSlider>

#include <algorithm>
#include <cmath>

namespace
{
// The opacity slider's resolution: 0.01.
const int OpacitySteps = 100;
const char* AxisNames[3] = { "x", "y", "z" };
}

//-----------------------------------------------------------------------------
pqGaussianWidgetRow::pqGaussianWidgetRow(int index, QWidget* parentWidget)
  : Superclass(parentWidget)
  , Index(index)
{
  this->setObjectName(QString("widgetRow%1").arg(index));
  this->setFrameShape(QFrame::StyledPanel);
  const QString suffix = QString::number(index);

  auto* number = new QLabel(QString::number(index + 1), this);
  number->setObjectName("number" + suffix);
  number->setToolTip("Widget number (its position in GaussianWidgets)");

  this->Visible = new QCheckBox(this);
  this->Visible->setObjectName("visible" + suffix);
  this->Visible->setToolTip("Shown: unchecked, the widget is kept but draws nothing "
                            "(opacity 0 in GaussianWidgets; its opacity comes back when checked)");

  this->Name = new QLineEdit(this);
  this->Name->setObjectName("name" + suffix);
  this->Name->setPlaceholderText(QString("Widget %1").arg(index + 1));
  this->Name->setToolTip("Name of the widget, shown in the volume view's legend "
                         "(seeded widgets are named after what they select)");

  this->Colour = new pqColorChooserButton(this);
  this->Colour->setObjectName("colour" + suffix);
  this->Colour->setToolTip("Colour of the widget");
  this->Colour->setShowAlphaChannel(false);

  this->Opacity = new QSlider(Qt::Horizontal, this);
  this->Opacity->setObjectName("opacity" + suffix);
  this->Opacity->setRange(0, OpacitySteps);
  this->Opacity->setToolTip("Peak opacity of the widget (0..1)");
  this->OpacityValue = new QLabel(this);
  this->OpacityValue->setObjectName("opacityValue" + suffix);
  // Room for "1.00" so the row does not jump while dragging.
  this->OpacityValue->setMinimumWidth(this->fontMetrics().horizontalAdvance("0.000"));

  this->Sigma = this->newSpinBox("sigma" + suffix);
  this->Sigma->setToolTip("Width sigma of the Gaussian in reduced-domain units (> 0)");
  for (int axis = 0; axis < 3; ++axis)
  {
    this->Centre[axis] = this->newSpinBox(QString("c%1%2").arg(AxisNames[axis]).arg(index));
    // No arrows: three boxes side by side fit the default dock width (wheel and
    // keyboard still step them).
    this->Centre[axis]->setButtonSymbols(QAbstractSpinBox::NoButtons);
    this->Centre[axis]->setToolTip(
      QString("Centre %1 in the reduced domain (range: the coordinates' bounds)")
        .arg(AxisNames[axis]));
  }

  // Three short lines, so that a row fits the default width of the Properties dock:
  // shown, colour, name / opacity, sigma / centre.
  auto* grid = new QGridLayout(this);
  grid->setContentsMargins(4, 2, 4, 2);
  grid->setVerticalSpacing(2);
  grid->addWidget(number, 0, 0, 3, 1, Qt::AlignTop);
  auto* line1 = new QHBoxLayout();
  line1->addWidget(this->Visible);
  line1->addWidget(this->Colour);
  line1->addWidget(this->Name, 1);
  grid->addLayout(line1, 0, 1);
  auto* line2 = new QHBoxLayout();
  line2->addWidget(new QLabel("Opacity", this));
  line2->addWidget(this->Opacity, 1);
  line2->addWidget(this->OpacityValue);
  line2->addWidget(new QLabel(QString::fromUtf8("\xcf\x83"), this)); // sigma
  line2->addWidget(this->Sigma, 1);
  grid->addLayout(line2, 1, 1);
  auto* line3 = new QHBoxLayout();
  for (int axis = 0; axis < 3; ++axis)
  {
    line3->addWidget(new QLabel(AxisNames[axis], this));
    line3->addWidget(this->Centre[axis], 1);
  }
  grid->addLayout(line3, 2, 1);
  grid->setColumnStretch(1, 1);

  QObject::connect(this->Visible, &QCheckBox::toggled, this, [this](bool on) {
    if (!this->Updating)
    {
      Q_EMIT this->visibilityEdited(this->Index, on);
    }
  });
  QObject::connect(
    this->Colour, &pqColorChooserButton::chosenColorChanged, this, [this](const QColor& c) {
      if (!this->Updating)
      {
        Q_EMIT this->colourEdited(this->Index, c.redF(), c.greenF(), c.blueF());
      }
    });
  QObject::connect(this->Opacity, &QSlider::valueChanged, this, [this](int v) {
    const double opacity = static_cast<double>(v) / OpacitySteps;
    this->showOpacity(opacity);
    if (!this->Updating)
    {
      Q_EMIT this->valueEdited(this->Index, OPACITY, opacity);
    }
  });
  QObject::connect(this->Opacity, &QSlider::sliderPressed, this,
    [this]() { Q_EMIT this->dragStarted(this->Index); });
  QObject::connect(this->Opacity, &QSlider::sliderReleased, this,
    [this]() { Q_EMIT this->dragFinished(this->Index); });
  QObject::connect(this->Name, &QLineEdit::editingFinished, this, [this]() {
    if (!this->Updating && this->Name->isModified())
    {
      this->Name->setModified(false);
      Q_EMIT this->nameEdited(this->Index, this->Name->text());
    }
  });
  QObject::connect(this->Sigma, QOverload<double>::of(&QDoubleSpinBox::valueChanged), this,
    [this](double v) {
      if (!this->Updating)
      {
        Q_EMIT this->valueEdited(this->Index, SIGMA, v);
      }
    });
  for (int axis = 0; axis < 3; ++axis)
  {
    QObject::connect(this->Centre[axis], QOverload<double>::of(&QDoubleSpinBox::valueChanged),
      this, [this, axis](double v) {
        if (!this->Updating)
        {
          Q_EMIT this->valueEdited(this->Index, CX + axis, v);
        }
      });
  }

  // A click or focus anywhere in the row selects its widget.
  for (QWidget* child : this->findChildren<QWidget*>())
  {
    child->installEventFilter(this);
  }
}

//-----------------------------------------------------------------------------
QDoubleSpinBox* pqGaussianWidgetRow::newSpinBox(const QString& name)
{
  auto* box = new QDoubleSpinBox(this);
  box->setObjectName(name);
  // One edit per Enter / focus change / arrow step, not one per keystroke (each edit is
  // an undo step and a render).
  box->setKeyboardTracking(false);
  return box;
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetRow::showOpacity(double opacity)
{
  this->OpacityValue->setText(QString::number(opacity, 'f', 2));
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetRow::setValues(const double values[8], bool visible)
{
  this->Updating = true;
  this->Visible->setChecked(visible);
  this->Colour->setChosenColor(QColor::fromRgbF(std::min(1.0, std::max(0.0, values[4])),
    std::min(1.0, std::max(0.0, values[5])), std::min(1.0, std::max(0.0, values[6]))));
  this->Opacity->setValue(static_cast<int>(std::lround(values[OPACITY] * OpacitySteps)));
  this->showOpacity(values[OPACITY]);
  // A value outside the spin box's range would be clamped on display: widen the range.
  auto show = [](QDoubleSpinBox* box, double v) {
    box->setRange(std::min(box->minimum(), v), std::max(box->maximum(), v));
    box->setValue(v);
  };
  show(this->Sigma, values[SIGMA]);
  for (int axis = 0; axis < 3; ++axis)
  {
    show(this->Centre[axis], values[CX + axis]);
  }
  this->Updating = false;
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetRow::setName(const QString& name)
{
  if (this->Name->text() != name && !this->Name->hasFocus())
  {
    this->Updating = true;
    this->Name->setText(name);
    this->Name->setModified(false);
    this->Updating = false;
  }
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetRow::setCentreRanges(const double ranges[3][2], int dimensions, double step)
{
  this->Updating = true;
  const int decimals = std::max(2, static_cast<int>(std::ceil(-std::log10(step))) + 1);
  for (int axis = 0; axis < 3; ++axis)
  {
    QDoubleSpinBox* box = this->Centre[axis];
    const double value = box->value();
    box->setDecimals(decimals);
    box->setSingleStep(step);
    box->setRange(std::min(ranges[axis][0], value), std::max(ranges[axis][1], value));
    box->setEnabled(axis < dimensions);
  }
  const double span = std::max({ ranges[0][1] - ranges[0][0], ranges[1][1] - ranges[1][0],
    ranges[2][1] - ranges[2][0], step });
  this->Sigma->setDecimals(decimals);
  this->Sigma->setSingleStep(step);
  this->Sigma->setRange(std::pow(10.0, -decimals), std::max(10 * span, this->Sigma->value()));
  this->Updating = false;
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetRow::setHighlighted(bool highlighted)
{
  // Named selector: the frame only, not its children.
  this->setStyleSheet(highlighted
      ? QString("QFrame#%1 { border: 2px solid palette(highlight); }").arg(this->objectName())
      : QString());
}

//-----------------------------------------------------------------------------
void pqGaussianWidgetRow::mousePressEvent(QMouseEvent* event)
{
  Q_EMIT this->activated(this->Index);
  this->Superclass::mousePressEvent(event);
}

//-----------------------------------------------------------------------------
bool pqGaussianWidgetRow::eventFilter(QObject* watched, QEvent* event)
{
  if (event->type() == QEvent::MouseButtonPress || event->type() == QEvent::FocusIn)
  {
    Q_EMIT this->activated(this->Index);
  }
  return this->Superclass::eventFilter(watched, event);
}

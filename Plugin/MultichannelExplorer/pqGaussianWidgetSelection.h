// Which Gaussian widget the user is working on, shared by the GUI parts that show the
// widgets of a "Gaussian TF Volume": the widget editor in the Properties panel and the
// draggable handles in the reduced-domain view. Selecting a row of the editor highlights
// that widget's handle; grabbing a handle selects the editor's row.
#ifndef pqGaussianWidgetSelection_h
#define pqGaussianWidgetSelection_h

#include <QObject>
#include <QPointer>

class pqProxy;
class vtkSMProxy;

class pqGaussianWidgetSelection : public QObject
{
  Q_OBJECT
  typedef QObject Superclass;

public:
  /** The one instance of the GUI process (created on first use, parented to the app). */
  static pqGaussianWidgetSelection* instance();

  /** The representation proxy whose widget is selected (nullptr: none), and its index. */
  vtkSMProxy* representation() const { return this->Representation; }
  int index() const { return this->Index; }

public Q_SLOTS:
  /** Selects widget `index` (-1: none) of `representation`'s GaussianWidgets. */
  void select(vtkSMProxy* representation, int index);

Q_SIGNALS:
  void selectionChanged(vtkSMProxy* representation, int index);

private:
  explicit pqGaussianWidgetSelection(QObject* parent);
  vtkSMProxy* Representation = nullptr; // not owned; cleared when the proxy goes away
  int Index = -1;
};

#endif

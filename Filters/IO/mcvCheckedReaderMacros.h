/**
 * The members every checked reader of this module declares (vtkCheckedNIFTIImageReader,
 * vtkCheckedMetaImageReader, vtkCheckedTIFFReader), declared once by
 * mcvCheckedReaderMembersMacro in the protected section of the reader's class:
 *
 * - RequestInformation checks the file's header against the file and the memory before
 *   anything is read, and refuses a bad file with one error that names it and the problem
 *   (CheckedReading.h: checkedRequestInformation),
 * - RequestData reads nothing from a refused file (checkedRequestData),
 * - Describe() is how every error starts ("NIfTI file '<name>'"),
 * - Refused says whether the last RequestInformation refused the file.
 *
 * The readers that check one file's header against that file and nothing else
 * (vtkCheckedNIFTIImageReader, vtkCheckedMetaImageReader) have the same class body past
 * New and vtkTypeMacro: defaulted construction, these members, no copies, and
 * CheckHeaderAgainstFile(), "" when the header and its data agree, else what is wrong in
 * one sentence. mcvCheckedHeaderReaderMacro(thisClass) declares that body once, last in
 * the class (it leaves the class in its private section).
 */
#ifndef mcvCheckedReaderMacros_h
#define mcvCheckedReaderMacros_h

#include <string> // for std::string

class vtkInformation;
class vtkInformationVector;

#define mcvCheckedReaderMembersMacro()                                                         \
  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,          \
    vtkInformationVector* outputVector) override;                                              \
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,                 \
    vtkInformationVector* outputVector) override;                                              \
  std::string Describe();                                                                      \
  bool Refused = false

#define mcvCheckedHeaderReaderMacro(thisClass)                                                 \
protected:                                                                                     \
  thisClass() = default;                                                                       \
  ~thisClass() override = default;                                                             \
  mcvCheckedReaderMembersMacro();                                                              \
                                                                                               \
private:                                                                                       \
  thisClass(const thisClass&) = delete;                                                        \
  void operator=(const thisClass&) = delete;                                                   \
  std::string CheckHeaderAgainstFile()

#endif

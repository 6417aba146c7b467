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

#endif

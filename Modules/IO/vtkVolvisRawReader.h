/**
 * @class   vtkVolvisRawReader
 * @brief   Reads headerless raw volumes named after the volvis.org convention.
 *
 * volvis.org distributes volumes as headerless binary files named
 * `Name.<C>.<X>x<Y>x<Z>.raw`: C components per voxel, X x Y x Z voxels, x
 * fastest, then y, then z. The dimensions come from the file name; the
 * scalar type (unsigned char by default), the byte order of multi-byte types,
 * the spacing and the origin are set by the user, since the file does not
 * hold them.
 *
 * The reader is streaming friendly: RequestInformation() reports the whole
 * extent from the file name alone, and RequestData() reads only the rows of
 * the requested update extent.
 *
 * A file that cannot be read, a name without dimensions, or a size that does
 * not match X * Y * Z * C * sizeof(type) (truncated or oversized) is reported
 * with vtkErrorMacro and gives an empty output.
 */

#ifndef vtkVolvisRawReader_h
#define vtkVolvisRawReader_h

#include "avosIOModule.h" // For export macro
#include "vtkImageAlgorithm.h"

class AVOSIO_EXPORT vtkVolvisRawReader : public vtkImageAlgorithm
{
public:
  static vtkVolvisRawReader* New();
  vtkTypeMacro(vtkVolvisRawReader, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The raw file, named `Name.<C>.<X>x<Y>x<Z>.raw`.
   */
  vtkSetFilePathMacro(FileName);
  vtkGetFilePathMacro(FileName);
  ///@}

  ///@{
  /**
   * Scalar type of the file: VTK_UNSIGNED_CHAR (default), VTK_CHAR,
   * VTK_SIGNED_CHAR, VTK_UNSIGNED_SHORT, VTK_SHORT, VTK_UNSIGNED_INT, VTK_INT,
   * VTK_FLOAT or VTK_DOUBLE.
   */
  vtkSetMacro(DataScalarType, int);
  vtkGetMacro(DataScalarType, int);
  void SetDataScalarTypeToUnsignedChar() { this->SetDataScalarType(VTK_UNSIGNED_CHAR); }
  void SetDataScalarTypeToUnsignedShort() { this->SetDataScalarType(VTK_UNSIGNED_SHORT); }
  void SetDataScalarTypeToShort() { this->SetDataScalarType(VTK_SHORT); }
  void SetDataScalarTypeToFloat() { this->SetDataScalarType(VTK_FLOAT); }
  ///@}

  ///@{
  /**
   * Whether multi-byte values are stored big endian. Default off (little
   * endian, as volvis.org's 16-bit files).
   */
  vtkSetMacro(DataByteOrderBigEndian, bool);
  vtkGetMacro(DataByteOrderBigEndian, bool);
  vtkBooleanMacro(DataByteOrderBigEndian, bool);
  ///@}

  ///@{
  /**
   * Voxel spacing (default 1, 1, 1; every component must be positive) and
   * origin (default 0, 0, 0).
   */
  vtkSetVector3Macro(DataSpacing, double);
  vtkGetVector3Macro(DataSpacing, double);
  vtkSetVector3Macro(DataOrigin, double);
  vtkGetVector3Macro(DataOrigin, double);
  ///@}

  ///@{
  /**
   * Name of the point scalar array. Default "density".
   */
  vtkSetStdStringFromCharMacro(ScalarArrayName);
  vtkGetCharFromStdStringMacro(ScalarArrayName);
  ///@}

  /**
   * Parse a volvis file name. Returns false when the name does not follow the
   * `Name.<C>.<X>x<Y>x<Z>.raw` convention.
   */
  static bool ParseFileName(const char* fileName, int& components, int dimensions[3]);

protected:
  vtkVolvisRawReader();
  ~vtkVolvisRawReader() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkVolvisRawReader(const vtkVolvisRawReader&) = delete;
  void operator=(const vtkVolvisRawReader&) = delete;

  // Checks the name, the scalar type, the spacing and the file size.
  bool ReadHeader(int& components, int dimensions[3]);

  char* FileName = nullptr;
  int DataScalarType = VTK_UNSIGNED_CHAR;
  bool DataByteOrderBigEndian = false;
  double DataSpacing[3] = { 1.0, 1.0, 1.0 };
  double DataOrigin[3] = { 0.0, 0.0, 0.0 };
  std::string ScalarArrayName = "density";
};

#endif

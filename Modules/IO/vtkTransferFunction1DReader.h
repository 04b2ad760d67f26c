/**
 * @class   vtkTransferFunction1DReader
 * @brief   Reads a 1D transfer function in the `.tf1d` text format.
 *
 * The `.tf1d` format is the one used by the authors of "Accurate Volume
 * Rendering based on Adaptive Numerical Integration" (Campagnolo, Celes and
 * de Figueiredo, SIBGRAPI 2015):
 *
 * @verbatim
 * linear            interpolation kind (only "linear" is defined)
 * 0                 unused flag
 * N                 number of colour knots
 * r g b value       N lines: colour in [0, 1] at a scalar value
 * M                 number of opacity knots
 * a value           M lines: extinction coefficient (per voxel unit) at a scalar value
 * @endverbatim
 *
 * The knots are kept exactly: the colour knots become the nodes of a
 * vtkColorTransferFunction, the opacity knots those of a vtkPiecewiseFunction
 * holding the extinction coefficient tau. Both functions are piecewise linear
 * and clamped outside their knots, as the format intends.
 *
 * FillVolumeProperty() puts them into a vtkVolumeProperty in one of two
 * opacity models:
 * - Extinction (the default): the scalar opacity function holds tau per voxel
 *   unit, unchanged. This is the paper's model, used by AVoS's mappers.
 * - VTK: VTK's opacity is an alpha per ScalarOpacityUnitDistance, so each
 *   knot becomes alpha = 1 - exp(-tau) and the unit distance is the length of
 *   one voxel unit (UnitDistance). This is exact at the knots only: between
 *   knots VTK interpolates alpha linearly, not tau.
 *
 * Every malformed file (missing, empty, unknown interpolation kind, missing or
 * extra numbers, zero knots, values not strictly increasing, NaN or infinite
 * numbers, colours outside [0, 1], negative extinction) is reported with
 * vtkErrorMacro; the functions are then left empty and Update() returns false.
 */

#ifndef vtkTransferFunction1DReader_h
#define vtkTransferFunction1DReader_h

#include "avosIOModule.h" // For export macro
#include "vtkNew.h"       // For vtkNew
#include "vtkObject.h"
#include "vtkTimeStamp.h" // For vtkTimeStamp

#include <iosfwd> // For std::istream
#include <string> // For std::string

class vtkColorTransferFunction;
class vtkPiecewiseFunction;
class vtkVolumeProperty;

class AVOSIO_EXPORT vtkTransferFunction1DReader : public vtkObject
{
public:
  static vtkTransferFunction1DReader* New();
  vtkTypeMacro(vtkTransferFunction1DReader, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The `.tf1d` file to read.
   */
  vtkSetFilePathMacro(FileName);
  vtkGetFilePathMacro(FileName);
  ///@}

  enum OpacityModels
  {
    OPACITY_MODEL_EXTINCTION = 0,
    OPACITY_MODEL_VTK = 1
  };

  ///@{
  /**
   * How FillVolumeProperty() writes the opacity knots (see the class
   * description). Default: extinction, the knots unchanged.
   */
  vtkSetClampMacro(OpacityModel, int, OPACITY_MODEL_EXTINCTION, OPACITY_MODEL_VTK);
  vtkGetMacro(OpacityModel, int);
  void SetOpacityModelToExtinction() { this->SetOpacityModel(OPACITY_MODEL_EXTINCTION); }
  void SetOpacityModelToVTK() { this->SetOpacityModel(OPACITY_MODEL_VTK); }
  ///@}

  ///@{
  /**
   * World length of one voxel unit, the length over which the file's
   * extinction applies. Used as ScalarOpacityUnitDistance in the VTK model.
   * Default 1.
   */
  vtkSetClampMacro(UnitDistance, double, 1e-12, VTK_DOUBLE_MAX);
  vtkGetMacro(UnitDistance, double);
  ///@}

  /**
   * Read the file unless nothing changed since the last successful read: no
   * setter called, and the same file with the same modification time and size. Returns true when
   * the functions hold a valid transfer function.
   */
  bool Update();

  /**
   * Colour knots (r, g, b at a scalar value). Valid after Update().
   */
  vtkColorTransferFunction* GetColorTransferFunction();

  /**
   * Opacity knots as extinction coefficients tau per voxel unit. Valid after
   * Update().
   */
  vtkPiecewiseFunction* GetExtinctionFunction();

  /**
   * Update(), then copy the colour and opacity knots into the property in the
   * current OpacityModel. Returns false (property unchanged) on a read error.
   */
  bool FillVolumeProperty(vtkVolumeProperty* property);

  ///@{
  /**
   * Update(), then the knots as a ParaView colour-map preset named `name`
   * (JSON, the format of ParaView's "Import Presets" and ImportPresets()):
   * RGBPoints from the colour knots, Points from the opacity knots in the
   * current OpacityModel (in VTK's, alpha per UnitDistance: set the volume
   * representation's ScalarOpacityUnitDistance to it). Numbers are written
   * with 17 significant digits, so the knots come back exactly. Empty, or
   * false for WriteParaViewPreset, on a read or write error (reported).
   */
  std::string GetParaViewPreset(const char* name);
  bool WriteParaViewPreset(const char* fileName, const char* name);
  ///@}

protected:
  vtkTransferFunction1DReader();
  ~vtkTransferFunction1DReader() override;

private:
  vtkTransferFunction1DReader(const vtkTransferFunction1DReader&) = delete;
  void operator=(const vtkTransferFunction1DReader&) = delete;

  bool Parse(std::istream& in);
  // Empties the functions after an error; returns false.
  bool Fail();

  char* FileName = nullptr;
  int OpacityModel = OPACITY_MODEL_EXTINCTION;
  double UnitDistance = 1.0;

  vtkNew<vtkColorTransferFunction> ColorFunction;
  vtkNew<vtkPiecewiseFunction> ExtinctionFunction;

  // What the last successful read saw, to skip re-reading an unchanged file.
  std::string ReadFileName;
  long long ReadFileTime = -1;
  long long ReadFileSize = -1;
  vtkTimeStamp ReadTime;
};

#endif

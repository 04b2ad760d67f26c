/**
 * @class   vtkAnalyticVolumeSource
 * @brief   Image data sampled from closed-form scalar fields.
 *
 * Produces a vtkImageData of any resolution over the box Bounds (default
 * [-1, 1]^3) with point scalars s = ScalarShift + ScalarScale * f(x), where f
 * is one of:
 * - Constant: f = 0, so s = ScalarShift everywhere.
 * - LinearRamp: f = x[RampAxis], the world coordinate along one axis. A
 *   linear field is reproduced exactly by trilinear interpolation, so
 *   integrals along any ray through it have closed forms (exact oracles).
 * - SphereDistance: f = |x - Center|, the distance to a point.
 * - MarschnerLobb: the test signal of Marschner and Lobb, "An evaluation of
 *   reconstruction filters for volume rendering" (IEEE Visualization 1994),
 *   rho(x, y, z) = (1 - sin(pi z / 2) + a (1 + cos(2 pi fM cos(pi r / 2))))
 *   / (2 (1 + a)), r = sqrt(x^2 + y^2), with a = 0.25 and fM = 6, in [0, 1],
 *   evaluated on the world coordinates (its natural domain is [-1, 1]^3).
 *
 * The output is float (default) or double. The source is streaming friendly:
 * it fills only the requested update extent, in parallel over z slices.
 */

#ifndef vtkAnalyticVolumeSource_h
#define vtkAnalyticVolumeSource_h

#include "avosFiltersSourcesModule.h" // For export macro
#include "vtkImageAlgorithm.h"

class AVOSFILTERSSOURCES_EXPORT vtkAnalyticVolumeSource : public vtkImageAlgorithm
{
public:
  static vtkAnalyticVolumeSource* New();
  vtkTypeMacro(vtkAnalyticVolumeSource, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Functions
  {
    CONSTANT = 0,
    LINEAR_RAMP,
    SPHERE_DISTANCE,
    MARSCHNER_LOBB
  };

  ///@{
  /**
   * The scalar field. Default SphereDistance.
   */
  vtkSetClampMacro(Function, int, CONSTANT, MARSCHNER_LOBB);
  vtkGetMacro(Function, int);
  void SetFunctionToConstant() { this->SetFunction(CONSTANT); }
  void SetFunctionToLinearRamp() { this->SetFunction(LINEAR_RAMP); }
  void SetFunctionToSphereDistance() { this->SetFunction(SPHERE_DISTANCE); }
  void SetFunctionToMarschnerLobb() { this->SetFunction(MARSCHNER_LOBB); }
  ///@}

  ///@{
  /**
   * Number of samples along x, y and z (each at least 1). Default 64^3.
   */
  vtkSetVector3Macro(Dimensions, int);
  vtkGetVector3Macro(Dimensions, int);
  ///@}

  ///@{
  /**
   * World box covered by the samples: (xmin, xmax, ymin, ymax, zmin, zmax),
   * each max above its min. Default [-1, 1]^3. Spacing is
   * (max - min) / (dimension - 1), or 1 along an axis with one sample.
   */
  vtkSetVector6Macro(Bounds, double);
  vtkGetVector6Macro(Bounds, double);
  ///@}

  ///@{
  /**
   * s = ScalarShift + ScalarScale * f(x). Defaults 0 and 1.
   */
  vtkSetMacro(ScalarShift, double);
  vtkGetMacro(ScalarShift, double);
  vtkSetMacro(ScalarScale, double);
  vtkGetMacro(ScalarScale, double);
  ///@}

  ///@{
  /**
   * Axis of the linear ramp: 0 (x, default), 1 (y) or 2 (z).
   */
  vtkSetClampMacro(RampAxis, int, 0, 2);
  vtkGetMacro(RampAxis, int);
  ///@}

  ///@{
  /**
   * Centre of the sphere distance field. Default (0, 0, 0).
   */
  vtkSetVector3Macro(Center, double);
  vtkGetVector3Macro(Center, double);
  ///@}

  ///@{
  /**
   * VTK_FLOAT (default) or VTK_DOUBLE.
   */
  vtkSetMacro(OutputScalarType, int);
  vtkGetMacro(OutputScalarType, int);
  void SetOutputScalarTypeToFloat() { this->SetOutputScalarType(VTK_FLOAT); }
  void SetOutputScalarTypeToDouble() { this->SetOutputScalarType(VTK_DOUBLE); }
  ///@}

  /**
   * f at a world point, for the current Function (without shift and scale).
   * Tests use it as the exact field.
   */
  double EvaluateFunction(const double x[3]) const;

protected:
  vtkAnalyticVolumeSource();
  ~vtkAnalyticVolumeSource() override = default;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkAnalyticVolumeSource(const vtkAnalyticVolumeSource&) = delete;
  void operator=(const vtkAnalyticVolumeSource&) = delete;

  bool CheckParameters();
  void ComputeSpacing(double spacing[3]) const;

  int Function = SPHERE_DISTANCE;
  int Dimensions[3] = { 64, 64, 64 };
  double Bounds[6] = { -1.0, 1.0, -1.0, 1.0, -1.0, 1.0 };
  double ScalarShift = 0.0;
  double ScalarScale = 1.0;
  int RampAxis = 0;
  double Center[3] = { 0.0, 0.0, 0.0 };
  int OutputScalarType = VTK_FLOAT;
};

#endif

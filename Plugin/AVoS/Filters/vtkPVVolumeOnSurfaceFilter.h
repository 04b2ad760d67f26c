/**
 * @class   vtkPVVolumeOnSurfaceFilter
 * @brief   vtkVolumeOnSurfaceFilter as ParaView's proxies drive it
 *
 * ParaView's server manager sets properties, not objects: this subclass owns
 * the camera the colours are assigned for (its position, focal point, view
 * up, view angle and projection as properties) and the volume property
 * (ParaView's colour and opacity transfer-function proxies, linear
 * interpolation). Everything else is vtkVolumeOnSurfaceFilter's, including
 * its piece handling (the surface's piece, the whole volume), but one case:
 * when the volume's producer also feeds the surface's branch (reader ->
 * contour, reader -> this filter), each process receives only its piece of
 * the volume, and this filter gathers the pieces of all processes of the
 * global controller into the whole volume (every process then holds it, as
 * with a producer of its own), again only when a piece changed.
 *
 * @sa vtkVolumeOnSurfaceFilter
 */
#ifndef vtkPVVolumeOnSurfaceFilter_h
#define vtkPVVolumeOnSurfaceFilter_h

#include "avosParaViewFiltersModule.h" // For export macro
#include "vtkNew.h"                    // For vtkNew
#include "vtkVolumeOnSurfaceFilter.h"

class vtkCamera;
class vtkColorTransferFunction;
class vtkPiecewiseFunction;
class vtkVolumeProperty;

class AVOSPARAVIEWFILTERS_EXPORT vtkPVVolumeOnSurfaceFilter : public vtkVolumeOnSurfaceFilter
{
public:
  static vtkPVVolumeOnSurfaceFilter* New();
  vtkTypeMacro(vtkPVVolumeOnSurfaceFilter, vtkVolumeOnSurfaceFilter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The camera the colours are assigned for (vtkCamera's meanings).
   */
  void SetCameraPosition(double x, double y, double z);
  void SetCameraFocalPoint(double x, double y, double z);
  void SetCameraViewUp(double x, double y, double z);
  void SetCameraViewAngle(double degrees);
  void SetCameraParallelProjection(int parallel);
  ///@}

  ///@{
  /**
   * The volume's colour and opacity functions (ParaView's lookup table and
   * opacity function of the volume's array).
   */
  void SetColorTransferFunction(vtkColorTransferFunction* colors);
  void SetScalarOpacityFunction(vtkPiecewiseFunction* opacity);
  ///@}

protected:
  vtkPVVolumeOnSurfaceFilter();
  ~vtkPVVolumeOnSurfaceFilter() override;

  vtkSmartPointer<vtkImageData> AssembleVolume(
    vtkImageData* received, vtkInformation* volumeInfo) override;

private:
  vtkPVVolumeOnSurfaceFilter(const vtkPVVolumeOnSurfaceFilter&) = delete;
  void operator=(const vtkPVVolumeOnSurfaceFilter&) = delete;

  vtkNew<vtkCamera> OwnCamera;
  vtkNew<vtkVolumeProperty> OwnProperty;
  // The volume last used (gathered, or received whole), and the
  // modification time of this process's scalars then: reused while no
  // process's piece changed, and kept when a new one holds the same values,
  // so that a camera change casts no ray again.
  vtkImageData* Keep(vtkImageData* volume, vtkMTimeType pieceTime);
  vtkSmartPointer<vtkImageData> Kept;
  vtkMTimeType KeptFrom = 0;
};

#endif

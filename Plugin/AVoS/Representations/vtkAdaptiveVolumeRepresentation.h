/**
 * @class   vtkAdaptiveVolumeRepresentation
 * @brief   ParaView's image volume representation rendered by vtkAdaptiveVolumeMapper
 *
 * The representation ParaView uses for volumes of image data (data
 * delivery, outline, ordered compositing of the pieces across ranks by
 * their bounds), with vtkAdaptiveVolumeMapper in place of the smart volume
 * mapper; its integration method, tolerance, sample distance and opacity
 * model are forwarded. Registered as the "AVoS Volume" representation type
 * of image data (Plugin/AVoS/AVoS.xml).
 *
 * @sa vtkAdaptiveVolumeMapper
 */
#ifndef vtkAdaptiveVolumeRepresentation_h
#define vtkAdaptiveVolumeRepresentation_h

#include "avosParaViewRepresentationsModule.h" // For export macro
#include "vtkImageVolumeRepresentation.h"

class vtkAdaptiveVolumeMapper;

class AVOSPARAVIEWREPRESENTATIONS_EXPORT vtkAdaptiveVolumeRepresentation
  : public vtkImageVolumeRepresentation
{
public:
  static vtkAdaptiveVolumeRepresentation* New();
  vtkTypeMacro(vtkAdaptiveVolumeRepresentation, vtkImageVolumeRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Forwarded to vtkAdaptiveVolumeMapper.
   */
  void SetIntegrationMethod(int method);
  void SetTolerance(double tolerance);
  void SetSampleDistance(double distance);
  void SetOpacityModel(int model);
  ///@}

protected:
  vtkAdaptiveVolumeRepresentation();
  ~vtkAdaptiveVolumeRepresentation() override;

private:
  vtkAdaptiveVolumeRepresentation(const vtkAdaptiveVolumeRepresentation&) = delete;
  void operator=(const vtkAdaptiveVolumeRepresentation&) = delete;

  vtkAdaptiveVolumeMapper* AdaptiveMapper; // this->VolumeMapper, typed
};

#endif

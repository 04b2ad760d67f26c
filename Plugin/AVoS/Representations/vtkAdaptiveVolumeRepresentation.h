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
 * What ParaView's volume representation passes: the property's settings
 * (colour, opacity, unit distance, interpolation, shading, independent or
 * dependent components from Map Scalars, Multi Components Mapping and the
 * separate opacity array) reach the mapper through the volume's property;
 * blend mode and cropping through the mapper; the colour map's vector mode
 * (magnitude or one component of a vector array) is given to the mapper
 * as ParaView gives it to vtkSmartVolumeMapper. What the mapper refuses
 * (isosurface and slice blends, 2D transfer functions) it refuses with an
 * error. The smart mapper's own settings, which this
 * mapper does not have, are accepted at their defaults and draw a warning
 * otherwise: the volume rendering mode, global illumination reach and
 * volumetric scattering blending.
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

  ///@{
  /**
   * vtkSmartVolumeMapper's settings, which vtkAdaptiveVolumeMapper does not
   * have: their defaults are accepted, any other value draws a warning
   * naming it (the image is vtkAdaptiveVolumeMapper's either way).
   */
  void SetRequestedRenderMode(int mode);
  void SetGlobalIlluminationReach(float reach);
  void SetVolumetricScatteringBlending(float blending);
  ///@}

protected:
  vtkAdaptiveVolumeRepresentation();
  ~vtkAdaptiveVolumeRepresentation() override;

  /**
   * The superclass's parameters, then the colour map's vector mode
   * (independent components) for the mapper, as ParaView gives it to
   * vtkSmartVolumeMapper.
   */
  void UpdateMapperParameters() override;

private:
  vtkAdaptiveVolumeRepresentation(const vtkAdaptiveVolumeRepresentation&) = delete;
  void operator=(const vtkAdaptiveVolumeRepresentation&) = delete;

  vtkAdaptiveVolumeMapper* AdaptiveMapper; // this->VolumeMapper, typed
};

#endif

#include "avosShadingFromRenderer.h"

#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkRenderer.h"
#include "vtkVolumeProperty.h"

#include "avos/engine/Frame.h"

#include <glm/glm.hpp>

#include <cmath>

std::string avos::ShadingFromRenderer(vtkRenderer* ren, vtkVolumeProperty* property,
  numerics::ShadingModel<double>& model, std::vector<double>& key)
{
  return ShadingFromLights(ren->GetLights(), ren->GetTwoSidedLighting() != 0, property, model, key);
}

std::string avos::ShadingFromLights(vtkLightCollection* lights, bool twoSided,
  vtkVolumeProperty* property, numerics::ShadingModel<double>& model, std::vector<double>& key)
{
  model = numerics::ShadingModel<double>();
  model.Ambient = property->GetAmbient(0);
  model.Diffuse = property->GetDiffuse(0);
  model.Specular = property->GetSpecular(0);
  model.SpecularPower = property->GetSpecularPower(0);
  model.TwoSided = twoSided;
  vtkCollectionSimpleIterator it;
  lights->InitTraversal(it);
  while (vtkLight* light = lights->GetNextLight(it))
  {
    if (!light->GetSwitch())
    {
      continue;
    }
    double position[3], focal[3];
    light->GetTransformedPosition(position);
    light->GetTransformedFocalPoint(focal);
    const glm::dvec3 from(position[0], position[1], position[2]);
    const glm::dvec3 towards = from - glm::dvec3(focal[0], focal[1], focal[2]);
    const double length = glm::length(towards);
    numerics::Light<double> l;
    l.Positional = light->GetPositional() != 0;
    l.Position = from;
    l.ConeAngle = light->GetConeAngle();
    l.Exponent = light->GetExponent();
    const double* attenuation = light->GetAttenuationValues();
    l.Attenuation = glm::dvec3(attenuation[0], attenuation[1], attenuation[2]);
    if (length > 0.0 && std::isfinite(length))
    {
      l.Direction = towards / length;
      l.Axis = -l.Direction;
    }
    else if (!l.Positional || l.IsSpot())
    {
      return "a light's position and focal point coincide";
    }
    const double intensity = light->GetIntensity();
    const double* diffuse = light->GetDiffuseColor();
    const double* specular = light->GetSpecularColor();
    l.Diffuse = intensity * glm::dvec3(diffuse[0], diffuse[1], diffuse[2]);
    l.Specular = intensity * glm::dvec3(specular[0], specular[1], specular[2]);
    model.Lights.push_back(l);
  }
  const std::string invalid = model.Validate();
  if (!invalid.empty())
  {
    return invalid;
  }
  key = { model.Ambient, model.Diffuse, model.Specular, model.SpecularPower,
    model.TwoSided ? 1.0 : 0.0 };
  for (const auto& light : model.Lights)
  {
    for (const glm::dvec3& v : { light.Direction, light.Diffuse, light.Specular, light.Position,
           light.Attenuation, light.Axis })
    {
      key.insert(key.end(), { v.x, v.y, v.z });
    }
    key.insert(key.end(), { light.Positional ? 1.0 : 0.0, light.ConeAngle, light.Exponent });
  }
  return std::string();
}

namespace
{
// The linear part of `gridToWorld` (row-major 4x4).
glm::dmat3 LinearPart(const double gridToWorld[16])
{
  glm::dmat3 linear;
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
    {
      linear[c][r] = gridToWorld[4 * r + c]; // glm: [column][row]
    }
  }
  return linear;
}
} // namespace

glm::dmat3 avos::NormalMatrix(const double gridToWorld[16])
{
  return glm::transpose(glm::inverse(LinearPart(gridToWorld)));
}

void avos::ShadeWith(const numerics::ShadingModel<double>& model, const double gridToWorld[16],
  engine::FrameMethod& method)
{
  method.Shading = &model;
  method.GridToWorld = LinearPart(gridToWorld);
  for (int r = 0; r < 3; ++r)
  {
    method.GridToWorldOffset[r] = gridToWorld[4 * r + 3];
  }
  method.NormalMatrix = NormalMatrix(gridToWorld);
}

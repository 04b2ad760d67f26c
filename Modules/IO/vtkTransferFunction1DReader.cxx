#include "vtkTransferFunction1DReader.h"

#include "vtkColorTransferFunction.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkVolumeProperty.h"

#include <vtksys/SystemTools.hxx>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <locale>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkTransferFunction1DReader);

namespace
{
// Larger counts are a corrupt file, not a transfer function.
constexpr long MaximumKnots = 1 << 20;

// Reads whitespace-separated tokens and reports where parsing failed.
class TokenStream
{
public:
  explicit TokenStream(std::istream& in)
    : In(in)
  {
  }

  bool Next(std::string& token, const char* what)
  {
    if (this->In >> token)
    {
      return true;
    }
    this->Error = std::string("unexpected end of file while reading ") + what;
    return false;
  }

  bool Number(double& value, const char* what)
  {
    std::string token;
    if (!this->Next(token, what))
    {
      return false;
    }
    char* end = nullptr;
    errno = 0;
    value = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0' || errno == ERANGE)
    {
      this->Error = "'" + token + "' is not a number (" + what + ")";
      return false;
    }
    if (!std::isfinite(value))
    {
      this->Error = "non-finite number '" + token + "' (" + what + ")";
      return false;
    }
    return true;
  }

  bool Integer(long& value, const char* what)
  {
    std::string token;
    if (!this->Next(token, what))
    {
      return false;
    }
    char* end = nullptr;
    errno = 0;
    value = std::strtol(token.c_str(), &end, 10);
    if (end == token.c_str() || *end != '\0' || errno == ERANGE)
    {
      this->Error = "'" + token + "' is not an integer (" + what + ")";
      return false;
    }
    return true;
  }

  bool AtEnd()
  {
    std::string token;
    return !(this->In >> token);
  }

  std::istream& In;
  std::string Error;
};

struct Knot
{
  double Value;
  double Data[3];
};

bool ReadKnots(TokenStream& tokens, int components, const char* what, std::vector<Knot>& knots)
{
  long count = 0;
  std::string countName = std::string("the number of ") + what + " knots";
  if (!tokens.Integer(count, countName.c_str()))
  {
    return false;
  }
  if (count <= 0)
  {
    tokens.Error =
      std::string("the file has no ") + what + " knots (count " + std::to_string(count) + ")";
    return false;
  }
  if (count > MaximumKnots)
  {
    tokens.Error =
      std::string("implausible number of ") + what + " knots: " + std::to_string(count);
    return false;
  }
  knots.resize(static_cast<std::size_t>(count));
  for (auto& knot : knots)
  {
    for (int c = 0; c < components; ++c)
    {
      if (!tokens.Number(knot.Data[c], what))
      {
        return false;
      }
    }
    if (!tokens.Number(knot.Value, "scalar value of a knot"))
    {
      return false;
    }
  }
  for (std::size_t i = 1; i < knots.size(); ++i)
  {
    if (!(knots[i].Value > knots[i - 1].Value))
    {
      tokens.Error = std::string(what) + " knot values are not strictly increasing (" +
        std::to_string(knots[i - 1].Value) + " then " + std::to_string(knots[i].Value) + ")";
      return false;
    }
  }
  return true;
}
}

//------------------------------------------------------------------------------
vtkTransferFunction1DReader::vtkTransferFunction1DReader() = default;

//------------------------------------------------------------------------------
vtkTransferFunction1DReader::~vtkTransferFunction1DReader()
{
  this->SetFileName(nullptr);
}

//------------------------------------------------------------------------------
vtkColorTransferFunction* vtkTransferFunction1DReader::GetColorTransferFunction()
{
  return this->ColorFunction;
}

//------------------------------------------------------------------------------
vtkPiecewiseFunction* vtkTransferFunction1DReader::GetExtinctionFunction()
{
  return this->ExtinctionFunction;
}

//------------------------------------------------------------------------------
bool vtkTransferFunction1DReader::Fail()
{
  this->ColorFunction->RemoveAllPoints();
  this->ExtinctionFunction->RemoveAllPoints();
  this->ReadFileName.clear();
  return false;
}

//------------------------------------------------------------------------------
bool vtkTransferFunction1DReader::Update()
{
  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro("No FileName was set.");
    return this->Fail();
  }

  vtksys::SystemTools::Stat_t status;
  if (vtksys::SystemTools::Stat(this->FileName, &status) != 0 ||
    vtksys::SystemTools::FileIsDirectory(this->FileName))
  {
    vtkErrorMacro("Cannot read transfer function file '" << this->FileName << "': no such file.");
    return this->Fail();
  }
  const long long fileTime = static_cast<long long>(status.st_mtime);
  const long long fileSize = static_cast<long long>(status.st_size);
  if (this->ReadFileName == this->FileName && this->ReadFileTime == fileTime &&
    this->ReadFileSize == fileSize && this->ReadTime.GetMTime() > this->GetMTime())
  {
    return true;
  }

  std::ifstream in(this->FileName);
  if (!in)
  {
    vtkErrorMacro("Cannot open transfer function file '" << this->FileName << "'.");
    return this->Fail();
  }
  if (!this->Parse(in))
  {
    return this->Fail();
  }
  this->ReadFileName = this->FileName;
  this->ReadFileTime = fileTime;
  this->ReadFileSize = fileSize;
  this->ReadTime.Modified();
  return true;
}

//------------------------------------------------------------------------------
bool vtkTransferFunction1DReader::Parse(std::istream& in)
{
  TokenStream tokens(in);
  std::vector<Knot> colors;
  std::vector<Knot> extinctions;

  auto fail = [this, &tokens]()
  {
    vtkErrorMacro(
      "Malformed transfer function file '" << this->FileName << "': " << tokens.Error << ".");
    return false;
  };

  std::string kind;
  if (!tokens.Next(kind, "the interpolation kind"))
  {
    return fail();
  }
  if (kind != "linear")
  {
    tokens.Error = "unsupported interpolation kind '" + kind + "' (only 'linear' is defined)";
    return fail();
  }
  long flag = 0;
  if (!tokens.Integer(flag, "the flag after the interpolation kind"))
  {
    return fail();
  }
  if (!ReadKnots(tokens, 3, "colour", colors) || !ReadKnots(tokens, 1, "opacity", extinctions))
  {
    return fail();
  }
  for (const auto& knot : colors)
  {
    for (double c : knot.Data)
    {
      if (c < 0.0 || c > 1.0)
      {
        tokens.Error = "colour component " + std::to_string(c) + " at value " +
          std::to_string(knot.Value) + " is outside [0, 1]";
        return fail();
      }
    }
  }
  for (const auto& knot : extinctions)
  {
    if (knot.Data[0] < 0.0)
    {
      tokens.Error = "negative extinction " + std::to_string(knot.Data[0]) + " at value " +
        std::to_string(knot.Value);
      return fail();
    }
  }
  if (!tokens.AtEnd())
  {
    tokens.Error = "unexpected content after the last opacity knot";
    return fail();
  }

  this->ColorFunction->RemoveAllPoints();
  for (const auto& knot : colors)
  {
    this->ColorFunction->AddRGBPoint(knot.Value, knot.Data[0], knot.Data[1], knot.Data[2]);
  }
  this->ExtinctionFunction->RemoveAllPoints();
  for (const auto& knot : extinctions)
  {
    this->ExtinctionFunction->AddPoint(knot.Value, knot.Data[0]);
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkTransferFunction1DReader::FillVolumeProperty(vtkVolumeProperty* property)
{
  if (!property)
  {
    vtkErrorMacro("FillVolumeProperty: the property is null.");
    return false;
  }
  if (!this->Update())
  {
    return false;
  }

  vtkNew<vtkColorTransferFunction> color;
  color->DeepCopy(this->ColorFunction);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->DeepCopy(this->ExtinctionFunction);
  if (this->OpacityModel == OPACITY_MODEL_VTK)
  {
    // alpha over one voxel unit of a medium with extinction tau: 1 - exp(-tau).
    double node[4];
    for (int i = 0; i < opacity->GetSize(); ++i)
    {
      opacity->GetNodeValue(i, node);
      node[1] = -std::expm1(-node[1]);
      opacity->SetNodeValue(i, node);
    }
    property->SetScalarOpacityUnitDistance(this->UnitDistance);
  }
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  return true;
}

//------------------------------------------------------------------------------
std::string vtkTransferFunction1DReader::GetParaViewPreset(const char* name)
{
  vtkNew<vtkVolumeProperty> property;
  if (!this->FillVolumeProperty(property))
  {
    return std::string();
  }
  std::ostringstream json;
  json.imbue(std::locale::classic()); // a decimal point whatever the user's locale
  json.precision(17);
  // The name as a JSON string: quotes, backslashes and control characters
  // escaped.
  json << "[\n  {\n    \"Name\": \"";
  for (const char* c = name ? name : ""; *c; ++c)
  {
    const unsigned char u = static_cast<unsigned char>(*c);
    if (u == '"' || u == '\\')
    {
      json << '\\' << *c;
    }
    else if (u < 0x20)
    {
      json << "\\u00"
           << "0123456789abcdef"[u >> 4] << "0123456789abcdef"[u & 15];
    }
    else
    {
      json << *c;
    }
  }
  json << "\",\n    \"ColorSpace\": \"RGB\",\n    \"RGBPoints\": [";
  vtkColorTransferFunction* color = property->GetRGBTransferFunction();
  double node[6];
  for (int i = 0; i < color->GetSize(); ++i)
  {
    color->GetNodeValue(i, node);
    json << (i ? ", " : "") << node[0] << ", " << node[1] << ", " << node[2] << ", " << node[3];
  }
  json << "],\n    \"Points\": [";
  vtkPiecewiseFunction* opacity = property->GetScalarOpacity();
  for (int i = 0; i < opacity->GetSize(); ++i)
  {
    opacity->GetNodeValue(i, node);
    json << (i ? ", " : "") << node[0] << ", " << node[1] << ", " << node[2] << ", " << node[3];
  }
  json << "]\n  }\n]\n";
  return json.str();
}

//------------------------------------------------------------------------------
bool vtkTransferFunction1DReader::WriteParaViewPreset(const char* fileName, const char* name)
{
  const std::string preset = this->GetParaViewPreset(name);
  if (preset.empty())
  {
    return false;
  }
  std::ofstream out(fileName ? fileName : "");
  out << preset;
  out.close();
  if (!out)
  {
    vtkErrorMacro(<< "Cannot write the preset to '" << (fileName ? fileName : "") << "'.");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkTransferFunction1DReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent
     << "OpacityModel: " << (this->OpacityModel == OPACITY_MODEL_VTK ? "VTK" : "Extinction")
     << "\n";
  os << indent << "UnitDistance: " << this->UnitDistance << "\n";
  os << indent << "ColorKnots: " << this->ColorFunction->GetSize() << "\n";
  os << indent << "ExtinctionKnots: " << this->ExtinctionFunction->GetSize() << "\n";
}

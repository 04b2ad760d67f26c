// Helpers shared by the C++ tests of all modules: scratch files and
// expected-error checks.
#ifndef avosTestHelpers_h
#define avosTestHelpers_h

#include "vtkAlgorithm.h"
#include "vtkCommand.h"
#include "vtkExecutive.h"
#include "vtkTestErrorObserver.h"
#include "vtkTestUtilities.h"

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

namespace avostest
{
// The test's scratch folder (-T), where the bad-input files are written.
inline std::string TempPath(int argc, char* argv[], const std::string& name)
{
  char* dir = vtkTestUtilities::GetArgOrEnvOrDefault("-T", argc, argv, "VTK_TEMP_DIR", ".");
  std::string path = std::string(dir) + "/" + name;
  delete[] dir;
  return path;
}

inline void WriteFile(const std::string& path, const std::string& content)
{
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << content;
}

// Counts and reports failed checks: `check(ok, "what")`, then
// `return check.Result();` at the end of the test.
class Checklist
{
public:
  void operator()(bool ok, const std::string& what)
  {
    if (!ok)
    {
      std::cerr << "FAIL " << what << "\n";
      ++this->Failures;
    }
  }
  int Result() const { return this->Failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE; }

private:
  int Failures = 0;
};

// Observes errors of an object and, for algorithms, of its executive, so that
// expected errors are checked instead of printed (ctest fails on "ERROR: ").
class ExpectedErrors
{
public:
  explicit ExpectedErrors(vtkObject* object)
  {
    object->AddObserver(vtkCommand::ErrorEvent, this->Observer);
    object->AddObserver(vtkCommand::WarningEvent, this->Observer);
    if (auto* algorithm = vtkAlgorithm::SafeDownCast(object))
    {
      algorithm->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, this->ExecutiveObserver);
    }
  }

  // True when the last operation raised an error containing `expected`.
  bool Check(const std::string& what, const std::string& expected)
  {
    const bool ok = this->Observer->GetError() &&
      this->Observer->GetErrorMessage().find(expected) != std::string::npos;
    if (!ok)
    {
      std::cerr << "FAIL " << what << ": expected an error containing '" << expected << "', got '"
                << this->Observer->GetErrorMessage() << "'\n";
    }
    this->Clear();
    return ok;
  }

  // True when the last operation raised a warning containing `expected`.
  bool CheckWarning(const std::string& what, const std::string& expected)
  {
    const bool ok = this->Observer->GetWarning() &&
      this->Observer->GetWarningMessage().find(expected) != std::string::npos;
    if (!ok)
    {
      std::cerr << "FAIL " << what << ": expected a warning containing '" << expected << "', got '"
                << this->Observer->GetWarningMessage() << "'\n";
    }
    this->Clear();
    return ok;
  }

  bool None(const std::string& what)
  {
    const bool ok = !this->Observer->GetError() && !this->Observer->GetWarning();
    if (!ok)
    {
      std::cerr << "FAIL " << what << ": unexpected error '" << this->Observer->GetErrorMessage()
                << "'\n";
    }
    this->Clear();
    return ok;
  }

  void Clear()
  {
    this->Observer->Clear();
    this->ExecutiveObserver->Clear();
  }

private:
  vtkNew<vtkTest::ErrorObserver> Observer;
  vtkNew<vtkTest::ErrorObserver> ExecutiveObserver;
};
}

#endif

#include "core/fmu/model_description.hpp"

#include <cstdint>
#include <cstdio>
#include <sstream>

#include "core/version.hpp"

namespace packsim {

namespace {

std::string xmlEscape(const std::string& in) {
  std::string out;
  for (char c : in) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string number(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

const char* typeElement(FmuType t) {
  switch (t) {
    case FmuType::Real: return "Real";
    case FmuType::Integer: return "Integer";
    case FmuType::Boolean: return "Boolean";
  }
  return "Real";
}

}  // namespace

std::string fmuGuid(const std::string& scenarioText) {
  const std::string text = scenarioText + "\n" + kVersion;
  uint64_t h1 = 1469598103934665603ULL, h2 = 1099511628211ULL * 31;
  for (unsigned char c : text) {
    h1 = (h1 ^ c) * 1099511628211ULL;
    h2 = (h2 ^ c) * 0x100000001b3ULL + 0x9e3779b97f4a7c15ULL;
  }
  char b[48];
  std::snprintf(b, sizeof b, "{%08x-%04x-%04x-%04x-%012llx}", static_cast<unsigned>(h1 >> 32),
                static_cast<unsigned>((h1 >> 16) & 0xffff), static_cast<unsigned>(h1 & 0xffff),
                static_cast<unsigned>(h2 >> 48), static_cast<unsigned long long>(h2 & 0xffffffffffffULL));
  return b;
}

std::string modelDescriptionXml(const Scenario& s, const std::vector<FmuVariable>& vars, const std::string& guid) {
  std::ostringstream x;
  x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<fmiModelDescription fmiVersion=\"2.0\" modelName=\"" << xmlEscape(s.name) << "\" guid=\"" << guid << "\"\n"
    << "  description=\"" << xmlEscape("packsim: " + (s.description.empty() ? s.name : s.description)) << "\"\n"
    << "  generationTool=\"packsim " << kVersion << "\" variableNamingConvention=\"flat\" numberOfEventIndicators=\"0\">\n"
    << "  <CoSimulation modelIdentifier=\"" << kFmuModelIdentifier << "\" canHandleVariableCommunicationStepSize=\"true\"\n"
    << "    canBeInstantiatedOnlyOncePerProcess=\"false\" canNotUseMemoryManagementFunctions=\"true\"\n"
    << "    canGetAndSetFMUstate=\"false\" canSerializeFMUstate=\"false\"/>\n";
  x << "  <UnitDefinitions>\n";
  for (const FmuUnit& u : fmuUnits()) {
    x << "    <Unit name=\"" << u.name << "\"><BaseUnit";
    if (u.kg) x << " kg=\"" << u.kg << "\"";
    if (u.m) x << " m=\"" << u.m << "\"";
    if (u.s) x << " s=\"" << u.s << "\"";
    if (u.A) x << " A=\"" << u.A << "\"";
    if (u.K) x << " K=\"" << u.K << "\"";
    x << "/></Unit>\n";
  }
  x << "  </UnitDefinitions>\n";
  x << "  <DefaultExperiment startTime=\"0\" stopTime=\"" << number(s.endTime_s()) << "\" stepSize=\""
    << number(s.output.interval_s) << "\"/>\n";
  x << "  <ModelVariables>\n";
  for (size_t i = 0; i < vars.size(); ++i) {
    const FmuVariable& v = vars[i];
    const bool in = v.causality == FmuCausality::Input;
    x << "    <!-- index " << i + 1 << " -->\n"
      << "    <ScalarVariable name=\"" << xmlEscape(v.name) << "\" valueReference=\"" << i << "\" description=\""
      << xmlEscape(v.description) << "\" causality=\"" << (in ? "input" : "output") << "\" variability=\""
      << (v.type == FmuType::Real ? "continuous" : "discrete") << "\"" << (in ? "" : " initial=\"calculated\"")
      << ">\n      <" << typeElement(v.type);
    if (!v.unit.empty()) x << " unit=\"" << v.unit << "\"";
    if (in) {
      if (v.type == FmuType::Real) x << " start=\"" << number(v.start) << "\"";
      else if (v.type == FmuType::Integer) x << " start=\"" << static_cast<long>(v.start) << "\"";
      else x << " start=\"" << (v.start != 0.0 ? "true" : "false") << "\"";
    }
    x << "/>\n    </ScalarVariable>\n";
  }
  x << "  </ModelVariables>\n  <ModelStructure>\n    <Outputs>\n";
  for (size_t i = 0; i < vars.size(); ++i)
    if (vars[i].causality == FmuCausality::Output) x << "      <Unknown index=\"" << i + 1 << "\" dependencies=\"\"/>\n";
  x << "    </Outputs>\n    <InitialUnknowns>\n";
  for (size_t i = 0; i < vars.size(); ++i)
    if (vars[i].causality == FmuCausality::Output) x << "      <Unknown index=\"" << i + 1 << "\"/>\n";  // on every input
  x << "    </InitialUnknowns>\n  </ModelStructure>\n</fmiModelDescription>\n";
  return x.str();
}

}  // namespace packsim

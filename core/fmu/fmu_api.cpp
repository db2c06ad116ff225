// The FMI 2.0 co-simulation C API over SimulationRun (core/sim/simulation.hpp).
//
//   instantiate        loads resources/scenario.yaml, checks the GUID, builds the table
//   enter init mode    inputs may be set; exit init mode: the run starts and its first
//                      tick (t = 0) samples, decides and actuates
//   doStep(t, h)       the BMS ticks in (t, t+h]: each advances the plant one tick under
//                      the held inputs, then samples, decides, actuates. h must be a
//                      whole number of BMS ticks (within 1e-9 relative), else fmi2Error
//   get / set          by value reference = row of fmuVariables(); an input once set
//                      replaces the scenario's value from the next tick on
//
// No exception crosses this boundary: every entry point catches and reports through
// the importer's logger with fmi2Error. Instances share nothing (several per process).
#include <fmi2Functions.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>
#include <type_traits>

#include "core/fmu/fmu_variables.hpp"
#include "core/fmu/model_description.hpp"
#include "core/scenario/load_scenario.hpp"
#include "core/sim/external_inputs.hpp"
#include "models/cell/curve.hpp"  // kZeroCelsius_K

namespace {

using namespace packsim;

enum class Phase { Instantiated, Initializing, Stepping, Terminated, Failed };

struct Instance {
  std::string name;
  fmi2CallbackFunctions cb{};
  bool loggingOn = false;
  Scenario scenario;
  std::vector<FmuVariable> vars;
  std::vector<double> inputValue;  // per row: the value an input holds (start until set)
  ExternalInputs ext;
  std::unique_ptr<SimulationRun> run;
  Phase phase = Phase::Instantiated;
  double time_s = 0.0;

  void log(fmi2Status st, const char* category, const std::string& msg) const {
    if (cb.logger && (loggingOn || st != fmi2OK)) cb.logger(cb.componentEnvironment, name.c_str(), st, category, "%s", msg.c_str());
  }
  fmi2Status error(const std::string& msg) {
    log(fmi2Error, "logStatusError", msg);
    return fmi2Error;
  }
};

// The ambient range a scenario accepts (core/scenario/load_pack.cpp), in K.
constexpr double kAmbientMin_K = -60.0 + kZeroCelsius_K, kAmbientMax_K = 100.0 + kZeroCelsius_K;

Instance* self(fmi2Component c) { return static_cast<Instance*>(c); }

// fmuResourceLocation is a URI: file:///path, file:/path or file://host/path.
std::string pathFromUri(std::string uri) {
  if (uri.rfind("file://", 0) == 0) {
    uri = uri.substr(7);
    if (!uri.empty() && uri[0] != '/') uri = uri.substr(uri.find('/'));  // a host name
  } else if (uri.rfind("file:", 0) == 0) {
    uri = uri.substr(5);
  }
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size()) {
      out += static_cast<char>(std::strtol(uri.substr(i + 1, 2).c_str(), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// Runs `f` with every exception turned into fmi2Error and a logged message.
template <typename F>
fmi2Status guarded(fmi2Component c, const char* what, F&& f) {
  if (!c) return fmi2Error;
  Instance& m = *self(c);
  try {
    return f(m);
  } catch (const std::exception& e) {
    m.phase = Phase::Failed;
    return m.error(std::string(what) + ": " + e.what());
  } catch (...) {
    m.phase = Phase::Failed;
    return m.error(std::string(what) + ": unknown error");
  }
}

void applyInput(Instance& m, size_t row, double v) {
  m.inputValue[row] = v;
  switch (m.vars[row].input) {
    case FmuInput::LoadCurrent:
    case FmuInput::LoadPower: m.ext.load_A_or_W = v; break;
    case FmuInput::Ambient: m.ext.ambient_C = v - kZeroCelsius_K; break;
    case FmuInput::EstopInternal: m.ext.estop_internal_pulled = v != 0.0; break;
    case FmuInput::EstopExternal: m.ext.estop_external_pulled = v != 0.0; break;
    case FmuInput::ChargerPresent: m.ext.charger_present = v != 0.0; break;
    case FmuInput::None: break;
  }
  if (m.run) m.run->setExternalInputs(m.ext);
}

template <typename V>
fmi2Status getValues(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, V value[], FmuType type) {
  return guarded(c, "get", [&](Instance& m) {
    for (size_t i = 0; i < nvr; ++i) {
      if (vr[i] >= m.vars.size() || m.vars[vr[i]].type != type)
        return m.error("value reference " + std::to_string(vr[i]) + " is not a variable of this type");
      const FmuVariable& v = m.vars[vr[i]];
      double x = 0.0;
      if (v.causality == FmuCausality::Input) x = m.inputValue[vr[i]];
      else if (m.run) x = v.get(*m.run);
      if constexpr (std::is_same_v<V, fmi2Real>) value[i] = x;
      else if constexpr (std::is_same_v<V, fmi2Integer>) value[i] = static_cast<fmi2Integer>(x);
      else value[i] = x != 0.0 ? fmi2True : fmi2False;
    }
    return fmi2OK;
  });
}

template <typename V>
fmi2Status setValues(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const V value[], FmuType type) {
  return guarded(c, "set", [&](Instance& m) {
    if (m.phase == Phase::Terminated || m.phase == Phase::Failed) return m.error("set after terminate or an error");
    const bool powerLoad = m.scenario.load.quantity == LoadProfile::Quantity::Power_W;
    for (size_t i = 0; i < nvr; ++i) {
      if (vr[i] >= m.vars.size() || m.vars[vr[i]].type != type || m.vars[vr[i]].causality != FmuCausality::Input)
        return m.error("value reference " + std::to_string(vr[i]) + " is not an input of this type");
      const FmuVariable& v = m.vars[vr[i]];
      if ((v.input == FmuInput::LoadCurrent && powerLoad) || (v.input == FmuInput::LoadPower && !powerLoad))
        return m.error(v.name + ": this scenario's load is a " + (powerLoad ? "power" : "current") + "; set " +
                       (powerLoad ? "load_power" : "load_current") + " instead");
      double x = 0.0;
      if constexpr (std::is_same_v<V, fmi2Boolean>) x = value[i] ? 1.0 : 0.0;
      else x = static_cast<double>(value[i]);
      if (!std::isfinite(x)) return m.error(v.name + ": the value is not finite");
      if (v.input == FmuInput::Ambient && !(x >= kAmbientMin_K && x <= kAmbientMax_K))
        return m.error(v.name + " = " + std::to_string(x) + " K is outside " + std::to_string(kAmbientMin_K) + " .. " +
                       std::to_string(kAmbientMax_K) + " K (-60 .. 100 degC, the scenario's range)");
      applyInput(m, vr[i], x);
    }
    return fmi2OK;
  });
}

}  // namespace

extern "C" {

const char* fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char* fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t, const fmi2String[]) {
  if (!c) return fmi2Error;
  self(c)->loggingOn = loggingOn != fmi2False;
  return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String guid, fmi2String resourceLocation,
                              const fmi2CallbackFunctions* functions, fmi2Boolean, fmi2Boolean loggingOn) {
  std::unique_ptr<Instance> m;
  try {
    m = std::make_unique<Instance>();
    m->name = instanceName ? instanceName : "packsim";
    if (functions) m->cb = *functions;
    m->loggingOn = loggingOn != fmi2False;
    if (fmuType != fmi2CoSimulation) {
      m->error("this FMU supports co-simulation only");
      return nullptr;
    }
    if (!resourceLocation) {
      m->error("no resource location: the scenario is in the FMU's resources/");
      return nullptr;
    }
    const std::string dir = pathFromUri(resourceLocation);
    const std::string file = dir + "/scenario.yaml";
    // A cell preset is in resources/cells, where the loader looks first.
    m->scenario = loadScenarioFile(file);
    const std::string want = fmuGuid(readScenarioText(file));
    if (!guid || want != guid) {
      m->error("GUID mismatch: the FMU's resources were not written with this modelDescription.xml");
      return nullptr;
    }
    m->vars = fmuVariables(m->scenario);
    for (const FmuVariable& v : m->vars) m->inputValue.push_back(v.start);
    m->log(fmi2OK, "logStatusOK", "instantiated from " + file);
    return m.release();
  } catch (const std::exception& e) {
    if (m) m->error(std::string("instantiate: ") + e.what());
  } catch (...) {
    if (m) m->error("instantiate: unknown error");
  }
  return nullptr;
}

void fmi2FreeInstance(fmi2Component c) { delete self(c); }

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean, fmi2Real, fmi2Real startTime, fmi2Boolean, fmi2Real) {
  return guarded(c, "setupExperiment", [&](Instance& m) {
    if (startTime != 0.0) return m.error("the scenario starts at t = 0 s, not " + std::to_string(startTime));
    return fmi2OK;
  });
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
  return guarded(c, "enterInitializationMode", [&](Instance& m) {
    if (m.phase != Phase::Instantiated) return m.error("enterInitializationMode: not after instantiate or reset");
    m.phase = Phase::Initializing;
    return fmi2OK;
  });
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
  return guarded(c, "exitInitializationMode", [&](Instance& m) {
    if (m.phase != Phase::Initializing) return m.error("exitInitializationMode: not in initialization mode");
    m.run = std::make_unique<SimulationRun>(m.scenario, RunEnd::Driver);
    m.run->setExternalInputs(m.ext);
    m.run->tick();  // t = 0
    m.time_s = 0.0;
    m.phase = Phase::Stepping;
    return fmi2OK;
  });
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean) {
  return guarded(c, "doStep", [&](Instance& m) {
    if (m.phase != Phase::Stepping) return m.error("doStep: not initialized, or terminated");
    const double tick_s = m.scenario.bms.tick_s;
    const double tol = 1e-9 * std::max(1.0, std::fabs(t) + std::fabs(h));
    if (std::fabs(t - m.time_s) > tol)
      return m.error("doStep: the communication point " + std::to_string(t) + " s is not the FMU's time " +
                     std::to_string(m.time_s) + " s");
    const double n = std::round(h / tick_s);
    if (h < 0.0 || std::fabs(n * tick_s - h) > tol)
      return m.error("doStep: the step " + std::to_string(h) + " s is not a whole number of BMS ticks (" +
                     std::to_string(tick_s) + " s)");
    for (long i = 0; i < static_cast<long>(n); ++i) {
      m.run->advance();
      m.run->tick();
    }
    m.time_s = m.run->time_s();
    return fmi2OK;
  });
}

fmi2Status fmi2Terminate(fmi2Component c) {
  return guarded(c, "terminate", [&](Instance& m) {
    m.phase = Phase::Terminated;
    return fmi2OK;
  });
}

fmi2Status fmi2Reset(fmi2Component c) {
  return guarded(c, "reset", [&](Instance& m) {
    m.run.reset();
    m.ext = ExternalInputs{};
    for (size_t i = 0; i < m.vars.size(); ++i) m.inputValue[i] = m.vars[i].start;
    m.time_s = 0.0;
    m.phase = Phase::Instantiated;
    return fmi2OK;
  });
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
  return getValues(c, vr, nvr, value, FmuType::Real);
}
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]) {
  return getValues(c, vr, nvr, value, FmuType::Integer);
}
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[]) {
  return getValues(c, vr, nvr, value, FmuType::Boolean);
}
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference[], size_t nvr, fmi2String[]) {
  return nvr == 0 ? fmi2OK : guarded(c, "getString", [](Instance& m) { return m.error("this FMU has no String variables"); });
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]) {
  return setValues(c, vr, nvr, value, FmuType::Real);
}
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[]) {
  return setValues(c, vr, nvr, value, FmuType::Integer);
}
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[]) {
  return setValues(c, vr, nvr, value, FmuType::Boolean);
}
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference[], size_t nvr, const fmi2String[]) {
  return nvr == 0 ? fmi2OK : guarded(c, "setString", [](Instance& m) { return m.error("this FMU has no String variables"); });
}

// Not supported (canGetAndSetFMUstate="false", no derivatives, no asynchronous steps).
static fmi2Status unsupported(fmi2Component c, const char* what) {
  return guarded(c, what, [what](Instance& m) { return m.error(std::string(what) + " is not supported by this FMU"); });
}
fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate*) { return unsupported(c, "fmi2GetFMUstate"); }
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate) { return unsupported(c, "fmi2SetFMUstate"); }
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate*) { return unsupported(c, "fmi2FreeFMUstate"); }
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate, size_t*) { return unsupported(c, "fmi2SerializedFMUstateSize"); }
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate, fmi2Byte[], size_t) { return unsupported(c, "fmi2SerializeFMUstate"); }
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte[], size_t, fmi2FMUstate*) {
  return unsupported(c, "fmi2DeSerializeFMUstate");
}
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference[], size_t, const fmi2ValueReference[], size_t,
                                        const fmi2Real[], fmi2Real[]) {
  return unsupported(c, "fmi2GetDirectionalDerivative");
}
fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference[], size_t, const fmi2Integer[], const fmi2Real[]) {
  return unsupported(c, "fmi2SetRealInputDerivatives");
}
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference[], size_t, const fmi2Integer[], fmi2Real[]) {
  return unsupported(c, "fmi2GetRealOutputDerivatives");
}
fmi2Status fmi2CancelStep(fmi2Component c) { return unsupported(c, "fmi2CancelStep"); }
fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind, fmi2Status*) { return unsupported(c, "fmi2GetStatus"); }
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real* value) {
  if (c && s == fmi2LastSuccessfulTime && value) {
    *value = self(c)->time_s;
    return fmi2OK;
  }
  return unsupported(c, "fmi2GetRealStatus");
}
fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind, fmi2Integer*) { return unsupported(c, "fmi2GetIntegerStatus"); }
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind, fmi2Boolean*) { return unsupported(c, "fmi2GetBooleanStatus"); }
fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind, fmi2String*) { return unsupported(c, "fmi2GetStringStatus"); }

}  // extern "C"

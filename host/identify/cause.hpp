// A candidate cause of misfit (the cause vocabulary of docs/data-format.md) as one object:
// its name and help, its extra parameters with their bounds, how it changes the specimen
// model or the reading, where its fits start, which values of it are physically plausible
// and how the report explains it. The fitter (fit.cpp) and the diagnosis (diagnose.cpp)
// know causes only through this interface, so a cause is one file under causes/ plus one
// line in causes/registry.cpp (docs/identify.md, "Adding a cause").
#pragma once

#include <cstddef>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "host/identify/measurement.hpp"
#include "host/identify/phases.hpp"
#include "host/identify/specimen.hpp"

namespace rheo::identify {

// One fitted parameter: its name, its bounds and whether it is optimised in log space.
struct ParamSpec {
  std::string name;  // e.g. "E1_Pa"
  double lower = 0.0;
  double upper = 0.0;
  bool log_scale = true;
};

// Parameters of the baseline (E1, c1, c2): every model starts with them, a cause's own
// parameters follow.
inline constexpr std::size_t kBaselineParams = 3;

// Data-driven scales used for bounds, starting points and a cause's data-fixed settings.
struct DataScales {
  double modulus_Pa = 1.0;  // peak stress / peak strain
  double duration_s = 1.0;
  double min_gap_s = 1.0;  // shortest sample spacing
  double peak_force_N = 1.0;
  double peak_strain = 0.0;   // largest plate_mm / height
  double first_time_s = 0.0;  // earliest positive sample time of any file
};

// The values of one parameter set, baseline first: E1, c1, c2, then the cause's own
// parameters in Cause::params() order.
class FittedValues {
 public:
  explicit FittedValues(const std::vector<double>& v) : v_(v) {}
  double E1() const { return v_[0]; }
  double c1() const { return v_[1]; }
  double c2() const { return v_[2]; }
  // The baseline's relaxation time (c1 + c2) / E1 [s].
  double tau1() const { return (v_[1] + v_[2]) / v_[0]; }
  // The cause's own parameter i.
  double operator[](std::size_t i) const { return v_[kBaselineParams + i]; }

 private:
  const std::vector<double>& v_;
};

struct FitResult;

// What a cause's explanation reads: the first fit file, its phases, the baseline's
// prediction and residuals there, both fits and the noise level.
struct EvidenceContext {
  const Measurement& m;
  const std::vector<Phase>& phases;
  const Prediction& baseline_prediction;
  const std::vector<double>& baseline_residual;  // measured - baseline, per sample
  const FitResult& baseline;
  const FitResult& extended;  // the baseline with this cause
  const DataScales& scales;
  double noise_sigma_N = 0.0;
};

// Material causes change the specimen; observation causes change only what the load cell
// reports of it.
enum class CauseSide { kMaterial, kObservation };
std::string cause_side_name(CauseSide s);  // "material" or "observation"

class Cause {
 public:
  Cause(std::string name, std::string help, CauseSide side)
      : name_(std::move(name)), help_(std::move(help)), side_(side) {}
  virtual ~Cause() = default;
  Cause(const Cause&) = delete;
  Cause& operator=(const Cause&) = delete;

  const std::string& name() const { return name_; }  // "second_relaxation_time", ...
  const std::string& help() const { return help_; }  // one line
  CauseSide side() const { return side_; }

  // The extra parameters appended to the baseline's, with bounds from the data's scales.
  virtual std::vector<ParamSpec> params(const DataScales& s) const = 0;
  // Writes the cause's values (and settings the data fix, not fitted) into the specimen
  // parameters the simulation runs.
  virtual void apply(FittedValues v, const DataScales& s, SpecimenParams& p) const {
    (void)v, (void)s, (void)p;
  }
  // Changes the simulated reading after the simulation, for observation effects that are
  // not part of the specimen model (the default leaves it alone).
  virtual void observe(FittedValues v, const DataScales& s, const Measurement& m,
                       Prediction& pr) const {
    (void)v, (void)s, (void)m, (void)pr;
  }
  // Starting values of the own parameters (one row per start) from a fitted baseline (only
  // E1, c1, c2 and tau1 of `baseline` are set).
  virtual std::vector<std::vector<double>> starts(FittedValues baseline,
                                                  const DataScales& s) const = 0;
  // Why fitted values lie outside the cause's physical range, "" when they do not: such a
  // fit describes something other than the cause and is not named.
  virtual std::string implausible(FittedValues v, const DataScales& s) const {
    (void)v, (void)s;
    return "";
  }
  // The report's sentence on what in the baseline's residuals shows this cause, with numbers
  // (diagnose appends the gain).
  virtual std::string explain(const EvidenceContext& e) const = 0;
  // Adds keys of its own to a fit's JSON (fit.json, details.json); none by default.
  virtual void annotate_fit_json(const DataScales& s, nlohmann::json& fit) const {
    (void)s, (void)fit;
  }

 private:
  std::string name_, help_;
  CauseSide side_;
};

using CausePtr = std::shared_ptr<const Cause>;

// The registry: the built-in causes of causes/registry.cpp, in the order the diagnosis
// tries them, followed by those registered at run time. Safe to call from any thread; a
// diagnosis works on the list as it was when it started.
std::vector<CausePtr> registered_causes();
// Appends a cause; throws rheo::Error when its name is taken (or "none"/"three_element").
void register_cause(CausePtr cause);
// Removes a cause by name; false when none has that name.
bool unregister_cause(const std::string& name);
// The cause of that name, null when none.
CausePtr find_cause(const std::string& name);
// The built-in causes (causes/registry.cpp), the registry's initial contents.
std::vector<CausePtr> builtin_causes();

// The registered cause names, comma-separated, for help and error texts.
std::string extension_names();
// The cause a model name asks for: "none" for "none" or "three_element", else a registered
// cause's name; throws rheo::Error naming the choices when unknown.
std::string extension_from_name(const std::string& name);

// Names the former enumeration gave causes, kept for code that names these two (the
// diagnosis benchmark among it); causes are identified by their name strings.
struct Extension {
  static inline const std::string kNone = "none";
  static inline const std::string kSecondRelaxationTime = "second_relaxation_time";
};

}  // namespace rheo::identify

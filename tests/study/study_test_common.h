// What the study tests share (study_test.cc, study_machines_test.cc, study_simulate_test.cc,
// study_engine_test.cc): the includes, the models' views, the study files written to the test's
// temporary directory, a view's parameters by name, and the check of the study through the model
// view against the generated model's.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "fourbar.h"
#include "fourbar_loaded.h"
#include "mechgen/core/view_runtime.h"
#include "mechgen/io/csv.h"
#include "mechgen/io/yaml_strict.h"
#include "mechgen/machines/view_machines.h"  // (before study/run.h: the view's machines compiled once)
#include "mechgen/analysis/view_analysis.h"    // (analysis/study.h; Study<ViewModel> extern: the library's)
#include "mechgen/study/random.h"
#include "mechgen/study/rows.h"
#include "mechgen/study/run.h"
#include "mechgen/study/samples.h"
#include "mechgen/study/shards.h"
#include "mechgen/study/spec.h"
#include "mechgen/study/tolerance.h"
#include "view_test_util.h"  // (tests/runtime)
#ifdef MECHGEN_STUDY_TEST_DESIGN_PRESS
#include "design_press.h"
#endif
#ifdef MECHGEN_STUDY_TEST_PENDULUM
#include "pendulum_spring.h"  // (its parameters' defaults, for the hand formulas)
#endif
#ifdef MECHGEN_STUDY_TEST_ENGINE
#include "engine_single.h"  // (its parameters' defaults, for the hand formulas)
#endif

// The models' views (generated/<model>_view.cc, in their libraries). The studies and the
// machines of every model but the four-bar run through them (Study<ViewModel> and the machines
// compiled once, in mechgen_runtime_view); of the generated models' studies, the four-bar's is
// compiled once (study_test.cc), the loaded four-bar's and the press's only for
// ExpectViewFirstOrderSame.
MECHGEN_DECLARE_MODEL_VIEW(fourbar)
MECHGEN_DECLARE_MODEL_VIEW(fourbar_loaded)
MECHGEN_DECLARE_MODEL_VIEW(slider_crank)
#ifdef MECHGEN_STUDY_TEST_SHAPER
MECHGEN_DECLARE_MODEL_VIEW(shaper)
#endif
#ifdef MECHGEN_STUDY_TEST_DESIGN_PRESS
MECHGEN_DECLARE_MODEL_VIEW(design_press)
#endif
#ifdef MECHGEN_STUDY_TEST_PENDULUM
MECHGEN_DECLARE_MODEL_VIEW(pendulum_spring)
#endif
#ifdef MECHGEN_STUDY_TEST_ENGINE
MECHGEN_DECLARE_MODEL_VIEW(engine_single)
#endif

// The study of the four-bar (every test file's) compiled once, in study_test.cc; the view's in
// the library (view_analysis.h).
extern template class mechgen::study::Study<mech::fourbar::Model>;

namespace mechgen_study_test {

namespace study = mechgen::study;

// A study file in the test's temporary directory.
inline std::string WriteStudy(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

inline study::StudySpec Read(const std::string& name, const std::string& text) {
  study::StudySpec spec;
  std::string error;
  EXPECT_TRUE(study::ReadStudy(WriteStudy(name, text), &spec, &error)) << error;
  return spec;
}

inline std::string ErrorOf(const std::string& name, const std::string& text) {
  study::StudySpec spec;
  std::string error;
  EXPECT_FALSE(study::ReadStudy(WriteStudy(name, text), &spec, &error));
  return error;
}

// ---- through the model view (issue 43) ---------------------------------------------------------

// A model's parameters through its view, set by name (tests/runtime/view_test_util.h).
using mechgen::view_test::ParamsOf;

// The study through the model view (Study<ViewModel>, the runtime compiled once, the view's
// Design, StaticsDesign and DesignChecks) against the generated model's: each metric at the
// nominal, its first-order gradient and why it has none, and the envelope point's dr_P/dp at
// every row (PathGradient), the same doubles to the bit (NaN where the generated one is NaN).
inline bool SameBits(double a, double b) { return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0; }
template <class M>
void ExpectViewFirstOrderSame(const mechgen::ModelView& view, const study::StudySpec& spec) {
  study::Study<M> fixed;
  study::Study<mechgen::ViewModel> through{mechgen::ViewModel(view)};
  std::string error;
  ASSERT_TRUE(fixed.Prepare(spec, &error)) << error;
  ASSERT_TRUE(through.Prepare(spec, &error)) << error;
  int finite = 0;
  for (size_t k = 0; k < spec.metrics.size(); ++k) {
    EXPECT_TRUE(SameBits(fixed.Value(k, fixed.nominal_rows()).value, through.Value(k, through.nominal_rows()).value))
        << spec.metrics[k].name;
    std::string why, view_why;
    const std::vector<double> g = fixed.Gradient(k, &why), h = through.Gradient(k, &view_why);
    EXPECT_EQ(why, view_why) << spec.metrics[k].name;
    ASSERT_EQ(g.size(), h.size());
    for (size_t p = 0; p < g.size(); ++p) {
      EXPECT_TRUE(SameBits(g[p], h[p])) << spec.metrics[k].name << " d/d" << spec.parameters[p].name << ": " << g[p]
                                        << " (generated), " << h[p] << " (view)";
      finite += std::isfinite(g[p]);
    }
  }
  EXPECT_GT(finite, 0);
  if (fixed.envelope_point() >= 0) {
    for (int i = 0; i < fixed.rows(); ++i)
      for (int axis = 0; axis < 2; ++axis) {
        const std::vector<double> g = fixed.PathGradient(i, axis), h = through.PathGradient(i, axis);
        for (size_t p = 0; p < g.size(); ++p)
          EXPECT_TRUE(SameBits(g[p], h[p])) << "row " << i << " axis " << axis << " d/d" << spec.parameters[p].name;
      }
  }
}

}  // namespace mechgen_study_test

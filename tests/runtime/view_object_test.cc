// Models loaded at run time as shared objects (issue 43), as `mechgen <command> MODEL` loads
// them into the runtime compiled once: <name>.cc + <name>_view.cc built with
// -DMECHGEN_VIEW_ENTRY (tests/runtime/CMakeLists.txt: view_object_fourbar, view_object_slider_crank
// from generated/, view_object_fourbar_edited from tests/runtime/models/fourbar_edited.yaml,
// models/fourbar.yaml with a longer crank and a second output point, generated under the same
// name `fourbar`).
//  - Two different models loaded in one process (RTLD_LOCAL: both export mechgen_model_view)
//    and swept on two threads at once give, bit for bit, what each gives alone, and what the
//    view linked into this program (mech::<name>::View(), the same generated code) gives.
//  - A model loaded, swept, unloaded (gone from the process: RTLD_NOLOAD finds nothing) and,
//    after an edit, loaded again from the same path: the view is the edited model's (its
//    points, its crank), its sweep equals the original model's at the edited crank length
//    (--set a=1.2: the generated code takes its parameters at run time, so the solve is the
//    same arithmetic), and nothing of the old object is read.
// Part of model_test.
#include <dlfcn.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "mechgen/core/view_runtime.h"

#if defined(MECHGEN_VIEW_OBJECT_fourbar) && defined(MECHGEN_VIEW_OBJECT_slider_crank) && \
    defined(MECHGEN_VIEW_OBJECT_fourbar_edited)
#define MECHGEN_HAVE_VIEW_OBJECTS 1
#include "fourbar.h"
namespace mech::fourbar {
const mechgen::ModelView& View();
}
#include "slider_crank.h"
namespace mech::slider_crank {
const mechgen::ModelView& View();
}
#endif

namespace mechgen {
namespace {

#ifdef MECHGEN_HAVE_VIEW_OBJECTS

// A shared object's view, loaded with RTLD_NOW | RTLD_LOCAL (as mechgen_view loads one).
struct Loaded {
  void* handle = nullptr;
  const ModelView* view = nullptr;
};

Loaded Load(const std::string& path) {
  Loaded l;
  l.handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (l.handle == nullptr) {
    ADD_FAILURE() << "cannot load " << path << ": " << dlerror();
    return l;
  }
  const auto entry = reinterpret_cast<ModelViewEntry>(dlsym(l.handle, kModelViewEntry));
  if (entry == nullptr) {
    ADD_FAILURE() << path << " has no " << kModelViewEntry;
    return l;
  }
  l.view = entry();
  return l;
}

// Every number of a sweep of the view's first input over its default range and back: the
// states' q, phi, K, L and points, and each step's status, in order.
std::vector<double> Sweep(const ModelView& view, const ViewParams* params = nullptr, int steps = 360) {
  const ViewModel model(view);
  ViewPositionSolver solver(model, position::Options(),
                            params != nullptr ? *params : ModelCalls<ViewModel>::DefaultParams(model));
  std::vector<double> out;
  position::Summary summary;
  out.push_back(static_cast<double>(solver.AssembleDefault(&summary)));
  ModelTypes<ViewModel>::VecQ q(view.nq);
  for (int i = 0; i <= 2 * steps; ++i) {
    const double t = i <= steps ? double(i) / steps : 2.0 - double(i) / steps;
    for (int k = 0; k < view.nq; ++k) q(k) = view.q_min[k] + t * (view.q_max[k] - view.q_min[k]);
    out.push_back(static_cast<double>(solver.MoveTo(q, &summary)));
    const auto& s = solver.state();
    out.insert(out.end(), s.phi.data(), s.phi.data() + s.phi.size());
    out.insert(out.end(), s.K.data(), s.K.data() + s.K.size());
    out.insert(out.end(), s.L.data(), s.L.data() + s.L.size());
    out.insert(out.end(), s.r_P.data(), s.r_P.data() + s.r_P.size());
  }
  return out;
}

::testing::AssertionResult SameBits(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return ::testing::AssertionFailure() << a.size() << " vs " << b.size() << " numbers";
  for (size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(&a[i], &b[i], sizeof(double)) != 0)
      return ::testing::AssertionFailure() << "number " << i << ": " << a[i] << " vs " << b[i];
  return ::testing::AssertionSuccess();
}

TEST(ViewObject, TwoModelsOnTwoThreads) {
  const Loaded fourbar = Load(MECHGEN_VIEW_OBJECT_fourbar);
  const Loaded slider = Load(MECHGEN_VIEW_OBJECT_slider_crank);
  ASSERT_NE(fourbar.view, nullptr);
  ASSERT_NE(slider.view, nullptr);
  // Each object's own entry point and view (RTLD_LOCAL), each compatible with this runtime.
  ASSERT_STREQ(fourbar.view->name, "fourbar");
  ASSERT_STREQ(slider.view->name, "slider_crank");
  ASSERT_NE(fourbar.view, &mech::fourbar::View());  // the object's, not this program's
  ASSERT_TRUE(ViewCompatible(*fourbar.view));
  ASSERT_TRUE(ViewCompatible(*slider.view));
  // Alone, then the two at once on two threads, several rounds started together.
  const std::vector<double> fourbar_alone = Sweep(*fourbar.view), slider_alone = Sweep(*slider.view);
  EXPECT_TRUE(SameBits(fourbar_alone, Sweep(mech::fourbar::View())));
  EXPECT_TRUE(SameBits(slider_alone, Sweep(mech::slider_crank::View())));
  EXPECT_GT(fourbar_alone.size(), 5000u);
  constexpr int kRounds = 8;
  std::vector<std::vector<double>> fourbar_runs(kRounds), slider_runs(kRounds);
  std::atomic<int> ready{0};
  auto run = [&ready](const ModelView* view, std::vector<std::vector<double>>* runs) {
    ready.fetch_add(1);
    while (ready.load() < 2) {
    }
    for (auto& r : *runs) r = Sweep(*view);
  };
  std::thread a(run, fourbar.view, &fourbar_runs), b(run, slider.view, &slider_runs);
  a.join();
  b.join();
  for (int r = 0; r < kRounds; ++r) {
    EXPECT_TRUE(SameBits(fourbar_runs[r], fourbar_alone)) << "fourbar, round " << r;
    EXPECT_TRUE(SameBits(slider_runs[r], slider_alone)) << "slider_crank, round " << r;
  }
  EXPECT_EQ(dlclose(fourbar.handle), 0);
  EXPECT_EQ(dlclose(slider.handle), 0);
}

TEST(ViewObject, LoadedUnloadedAndLoadedAgainAfterAnEdit) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(::testing::TempDir()) / "view_object_reload";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path path = dir / "model.so";
  fs::copy_file(MECHGEN_VIEW_OBJECT_fourbar, path);

  Loaded first = Load(path.string());
  ASSERT_NE(first.view, nullptr);
  ASSERT_STREQ(first.view->name, "fourbar");
  ASSERT_EQ(first.view->num_points, 1);
  const std::vector<double> before = Sweep(*first.view);
  ASSERT_EQ(dlclose(first.handle), 0);
  // Unloaded: no longer in the process.
  EXPECT_EQ(dlopen(path.c_str(), RTLD_NOW | RTLD_NOLOAD), nullptr);

  // The edit, built as a new file and renamed over the old one (as the cache puts an entry in
  // place: a file being loaded is never written).
  const fs::path part = dir / "model.so.part";
  fs::copy_file(MECHGEN_VIEW_OBJECT_fourbar_edited, part);
  fs::rename(part, path);
  Loaded second = Load(path.string());
  ASSERT_NE(second.view, nullptr);
  ASSERT_TRUE(ViewCompatible(*second.view));
  EXPECT_STREQ(second.view->name, "fourbar");
  EXPECT_EQ(second.view->num_points, 2);  // coupler.P and rocker.C
  const int a = FindParameter(*second.view, "a");
  ASSERT_GE(a, 0);
  EXPECT_EQ(second.view->params[a].default_value, 1.2);
  const std::vector<double> after = Sweep(*second.view);
  EXPECT_FALSE(SameBits(after, before));

  // The oracle: the original model (linked into this program) at a = 1.2, its coupler point
  // the edited model's first.
  ViewParams edited;
  DefaultParameters(mech::fourbar::View(), edited.data());
  edited.values[static_cast<size_t>(FindParameter(mech::fourbar::View(), "a"))] = 1.2;
  const ModelView& original = mech::fourbar::View();
  const ViewModel original_model(original), edited_model(*second.view);
  ViewPositionSolver x(original_model, position::Options(), edited), y(edited_model);
  ASSERT_EQ(x.AssembleDefault(nullptr), position::Status::kConverged);
  ASSERT_EQ(y.AssembleDefault(nullptr), position::Status::kConverged);
  ModelTypes<ViewModel>::VecQ q(1);
  int compared = 0;
  for (int i = 0; i <= 360; ++i) {
    q(0) = original.q_min[0] + (original.q_max[0] - original.q_min[0]) * i / 360.0;
    const position::Status sx = x.MoveTo(q, nullptr), sy = y.MoveTo(q, nullptr);
    ASSERT_EQ(sx, sy) << "step " << i;
    if (sx != position::Status::kConverged) continue;
    ++compared;
    const auto &s = x.state(), &t = y.state();
    for (int k = 0; k < s.phi.size(); ++k) ASSERT_EQ(s.phi(k), t.phi(k)) << "phi " << k << ", step " << i;
    for (int k = 0; k < s.K.size(); ++k) ASSERT_EQ(s.K(k), t.K(k)) << "K " << k << ", step " << i;
    ASSERT_EQ(s.r_P(0, 0), t.r_P(0, 0)) << "coupler.P x, step " << i;
    ASSERT_EQ(s.r_P(1, 0), t.r_P(1, 0)) << "coupler.P y, step " << i;
    // rocker.C: D + c (cos, sin) of the rocker's angle (a geometric invariant, not the code).
    const double c = 3.0, d = 4.0, rocker = t.phi(1);
    EXPECT_NEAR(t.r_P(0, 1), d + c * std::cos(rocker), 1e-12) << "step " << i;
    EXPECT_NEAR(t.r_P(1, 1), c * std::sin(rocker), 1e-12) << "step " << i;
  }
  EXPECT_EQ(compared, 361);
  EXPECT_EQ(dlclose(second.handle), 0);
  fs::remove_all(dir);
}

#endif  // MECHGEN_HAVE_VIEW_OBJECTS

}  // namespace
}  // namespace mechgen

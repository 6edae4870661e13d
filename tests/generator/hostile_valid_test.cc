// The hostile-but-valid model (tests/generator/hostile/hostile_valid.yaml): names that look
// like C++ keywords, macros and the generated code's own names (class_, new_, Eigen_, NAN_,
// errno_, T_, ...), and free text that tries to close the header's comments. Its header is
// compiled with -Wall -Wextra -Werror here, in its model library and standalone in ISO C++17
// (tests/generator/CMakeLists.txt); this test checks that what the comments carried stayed
// in comments, and that the mechanism it describes closes, against the four-bar's geometry
// written out from the parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "class_model.h"

namespace {

namespace gen = mech::class_model;
using M = gen::Model;

// The header without its comments (// and /* */), string literals kept.
std::string Code(const std::string& text) {
  std::string out;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '"') {
      const size_t end = text.find('"', i + 1);
      out += text.substr(i, end - i + 1);
      i = end;
    } else if (text.compare(i, 2, "//") == 0) {
      i = text.find('\n', i) - 1;
    } else if (text.compare(i, 2, "/*") == 0) {
      i = text.find("*/", i + 2) + 1;
      out += ' ';
    } else {
      out += text[i];
    }
  }
  return out;
}

TEST(HostileValid, FreeTextStaysInComments) {
  std::ifstream in(MECHGEN_HOSTILE_HEADER, std::ios::binary);
  ASSERT_TRUE(in) << MECHGEN_HOSTILE_HEADER;
  std::ostringstream os;
  os << in.rdbuf();
  const std::string header = os.str();
  // The text is there, with its comment delimiters broken up ...
  EXPECT_NE(header.find("Four-bar *\\/ int injected_from_title = 0; /\\* with keyword-like names"), std::string::npos);
  EXPECT_NE(header.find("tries to close itself: *\\/ int injected_from_description = 0; /\\*"), std::string::npos);
  EXPECT_NE(header.find("///< crank AB *\\/ int injected_from_doc = 0; /\\* still a comment"), std::string::npos);
  EXPECT_NE(header.find("Unicode stays as written: \xce\xb8, \xcf\x86, Gr\xc3\xbc" "bler"), std::string::npos);
  // ... and none of it reaches the code.
  const std::string code = Code(header);
  EXPECT_EQ(code.find("injected"), std::string::npos);
  EXPECT_NE(code.find("namespace mech::class_model"), std::string::npos);
}

TEST(HostileValid, NamesAreCarriedAsWritten) {
  EXPECT_STREQ(M::kName, "class_model");
  EXPECT_STREQ(M::kLinkNames[1], "new_");
  EXPECT_STREQ(M::kQNames[0], "theta_new_");
  EXPECT_STREQ(M::kPointNames[0], "Eigen_.errno_");
  const gen::Params<double> p;
  EXPECT_EQ(p.class_, 1.0);
  EXPECT_EQ(p.delete_me, 3.5);
  EXPECT_EQ(p.L, 3.0);
  EXPECT_EQ(p.NAN_, 4.0);
  const gen::Params<float> pf = p.Cast<float>();
  EXPECT_EQ(pf.Scalar_, 1.5f);
}

TEST(HostileValid, SolvesTheFourBarItDescribes) {
  const gen::Params<double> p;
  gen::Vec<double, M::kNphi> phi;
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[static_cast<size_t>(i)];
  for (int k = 0; k <= 36; ++k) {
    gen::Vec<double, M::kNq> q;
    q(0) = k * 10.0 * M_PI / 180;
    const auto report = gen::SolvePositions(p, q, &phi, M::kDefaultModes);
    ASSERT_EQ(report.status, gen::SolveStatus::kConverged) << "at " << 10 * k << " deg";
    // B on the crank, C from the coupler and from the rocker: the loop closes.
    const double th = q(0), th_c = phi(0), th_r = phi(1);
    const double bx = p.class_ * std::cos(th), by = p.class_ * std::sin(th);
    const double cx = bx + p.delete_me * std::cos(th_c), cy = by + p.delete_me * std::sin(th_c);
    const double rx = p.NAN_ + p.L * std::cos(th_r), ry = p.L * std::sin(th_r);
    EXPECT_NEAR(cx, rx, 1e-12);
    EXPECT_NEAR(cy, ry, 1e-12);
    // The coupler point at (Scalar_, p2) in the coupler's frame, from B.
    gen::Coefficients<double> c;
    gen::EvalCoefficients(p, q, phi, &c);
    EXPECT_NEAR(c.r_P(0, 0), bx + p.Scalar_ * std::cos(th_c) - p.p2 * std::sin(th_c), 1e-12);
    EXPECT_NEAR(c.r_P(1, 0), by + p.Scalar_ * std::sin(th_c) + p.p2 * std::cos(th_c), 1e-12);
  }
}

}  // namespace

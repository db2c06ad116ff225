// yamlFlowText (core/scenario/provenance.hpp) writes a list of plain numbers itself
// instead of through YAML::Emitter: the same text as the Emitter for every node,
// those lists and anything else (quoted, tagged, aliased, nested values, other scalars).
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "core/scenario/provenance.hpp"

namespace packsim {
namespace {

std::string emitterText(const YAML::Node& n) {
  YAML::Emitter out;
  out.SetMapFormat(YAML::Flow);
  out.SetSeqFormat(YAML::Flow);
  out << n;
  return out.c_str();
}

TEST(YamlFlowText, IsTheEmittersTextForEveryNode) {
  const std::vector<std::string> fixed = {
      "a:\n  - 0.0\n  - 4.999\n  - -28.0\n", "a: [1, 2.5, -3e-5, 1E+7, 5., -0]\n", "a: []\n", "a: [\"1.0\", '2']\n",
      "a: [1, ~, null, x y, q]\n", "a: 5\n", "a: {x: 1, y: [1, 2]}\n", "a:\n  - [1, 2]\n  - 3\n",
      "a: [.inf, -.inf, .nan, 1e400, 0x10, +5, 01, 1_000, 1e, -, .5]\n", "b: &x 7\na: [*x, 1, *x]\n",
      "b: &x 7\na: [*x, 1]\n", "a: !!seq [1, 2]\n", "a: [!!float 1, 2]\n", "a: [!x 1, 2]\n", "a: &l [1, 2]\n"};
  std::vector<std::string> docs = fixed;
  // Lists of random bits of YAML: numbers and near-numbers, in flow and block style.
  const char* atoms[] = {"0", "1", "9", "12", "-", "+", ".", "e", "E", "x", "_", " ", "'", "\"", "~", ":", ",",
                         "#", "inf", "00", "5.", "e+", "e-", "null", "!!float ", "&a ", "*a", "[", "]"};
  std::mt19937 rng(7);
  for (int k = 0; k < 3000; ++k) {
    const bool block = rng() % 3 == 0;
    std::string doc = rng() % 8 == 0 ? "b: &a 7\n" : "";
    doc += block ? "a:\n" : "a: [";
    const int items = static_cast<int>(rng() % 4);
    for (int j = 0; j < items; ++j) {
      std::string item;
      for (unsigned q = 0, parts = 1 + rng() % 4; q < parts; ++q) item += atoms[rng() % (sizeof atoms / sizeof *atoms)];
      if (rng() % 3 == 0)
        item = std::to_string(static_cast<int>(rng() % 100000) - 50000) + (rng() % 2 ? "." + std::to_string(rng() % 1000) : "") +
               (rng() % 3 == 0 ? "e" + std::to_string(static_cast<int>(rng() % 40) - 20) : "");
      if (rng() % 10 == 0) item = "\"" + item + "\"";
      doc += block ? "  - " + item + "\n" : (j ? ", " : "") + item;
    }
    doc += block ? (items == 0 ? "  []\n" : "") : "]\n";
    docs.push_back(doc);
  }
  int compared = 0;
  for (const std::string& doc : docs) {
    YAML::Node root, n;
    std::string expected;
    try {
      root = YAML::Load(doc);
      n = root["a"];
      expected = emitterText(n);
    } catch (const YAML::Exception&) {
      continue;  // not YAML, or nothing the Emitter writes
    }
    EXPECT_EQ(yamlFlowText(n), expected) << doc;
    ++compared;
  }
  EXPECT_GT(compared, 1500);
}

}  // namespace
}  // namespace packsim

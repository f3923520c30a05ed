// ims-replicate: writes IMS test 2 (or any IMS-format merged table) with every channel copied N times, as
// make_replicated_variant builds it (ims_variants.hpp): a wide asset group for deploy/launch.sh --features.
// Deterministic: the same base table, copies, noise and seed give a byte-identical file.
//   ims-replicate --base deploy/data/ims2-features/merged_dataset_BearingTest_2.csv --copies 5 --out FILE.csv
//                 [--seed N] [--noise 0.03]
#include "ims_variants.hpp"

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

namespace {

int usage(const char* problem) {
  std::fprintf(stderr, "ims-replicate: %s\nusage: ims-replicate --base MERGED_TABLE.csv --copies N --out FILE.csv "
               "[--seed N] [--noise SD]\n", problem);
  return 2;
}

bool parse_number(const char* text, double& out) {
  char* end = nullptr;
  out = std::strtod(text, &end);
  return end != text && *end == '\0';
}

}  // namespace

int main(int argc, char** argv) {
  std::string base_path, out_path;
  double copies = 0.0, seed = 32.0, noise = 0.03;
  for (int i = 1; i < argc; i += 2) {
    const std::string key = argv[i];
    if (key == "--help" || key == "-h") {
      std::printf("ims-replicate --base MERGED_TABLE.csv --copies N --out FILE.csv [--seed N (32)] [--noise SD (0.03)]\n"
                  "copy c of every channel = base x (1 + 0.1 c) x (1 + SD x N(0, 1)) per cell; columns channel-major\n");
      return 0;
    }
    if (i + 1 >= argc) return usage(("option " + key + " needs a value").c_str());
    const char* value = argv[i + 1];
    if (key == "--base") base_path = value;
    else if (key == "--out") out_path = value;
    else if (key == "--copies" && parse_number(value, copies) && copies >= 1 && copies <= 16 && copies == static_cast<int>(copies)) {}
    else if (key == "--seed" && parse_number(value, seed) && seed >= 0 && seed == static_cast<double>(static_cast<std::uint64_t>(seed))) {}
    else if (key == "--noise" && parse_number(value, noise) && noise >= 0.0 && noise <= 0.1) {}
    else return usage(("bad option or value: " + key + " " + value + " (--copies 1..16, --seed >= 0, --noise 0..0.1)").c_str());
  }
  if (base_path.empty() || out_path.empty() || copies < 1) return usage("--base, --copies and --out are required");
  try {
    const auto base = causal::testing::read_base_run(base_path);
    const auto v = causal::testing::make_replicated_variant(base, static_cast<int>(copies), static_cast<std::uint64_t>(seed), noise);
    causal::testing::write_variant_csv(v, out_path);
    std::printf("%s rows=%lld channels=%lld file=%s | %s\n", v.name.c_str(), static_cast<long long>(v.values.rows()),
                static_cast<long long>(v.values.cols()), out_path.c_str(), v.description.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ims-replicate: %s\n", e.what());
    return 1;
  }
  return 0;
}

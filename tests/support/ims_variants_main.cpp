// ims-variants: writes the robustness variants of IMS test 2 as IMS-format merged tables, one CSV per
// variant (and the two runs of ims_variants_unseen.hpp), plus variants.txt (one line per variant: name, rows, channels, healthy rows, failing channels,
// what was injected). Deterministic: the same base table and seed give byte-identical files.
//   ims-variants --base deploy/data/ims2-features/merged_dataset_BearingTest_2.csv --out DIR [--seed N]
#include "ims_variants.hpp"
#include "ims_variants_unseen.hpp"

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <string>

int main(int argc, char** argv) {
  std::string base_path, out_dir;
  std::uint64_t seed = 12;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i];
    if (key == "--base") base_path = argv[i + 1];
    else if (key == "--out") out_dir = argv[i + 1];
    else if (key == "--seed") seed = std::strtoull(argv[i + 1], nullptr, 10);
    else {
      std::fprintf(stderr, "ims-variants: unknown option %s\n", key.c_str());
      return 2;
    }
  }
  if (base_path.empty() || out_dir.empty()) {
    std::fprintf(stderr, "usage: ims-variants --base MERGED_TABLE.csv --out DIR [--seed N]\n");
    return 2;
  }
  try {
    const auto base = causal::testing::read_base_run(base_path);
    std::ofstream manifest(out_dir + "/variants.txt");
    auto variants = causal::testing::make_all_variants(base, seed);
    variants.push_back(causal::testing::make_relevelled_failure_variant(base, seed));
    variants.push_back(causal::testing::make_low_baseline_stretch_variant(base));
    for (const auto& v : variants) {
      const std::string path = out_dir + "/" + v.name + ".csv";
      causal::testing::write_variant_csv(v, path);
      std::string failing;
      for (int c : v.failing_channels) failing += (failing.empty() ? "" : ";") + v.channel_names[static_cast<std::size_t>(c)];
      char line[512];
      std::snprintf(line, sizeof line, "%s rows=%lld channels=%lld healthy_rows=%zu failing=\"%s\" file=%s | %s\n",
                    v.name.c_str(), static_cast<long long>(v.values.rows()), static_cast<long long>(v.values.cols()),
                    v.healthy_end, failing.c_str(), path.c_str(), v.description.c_str());
      manifest << line;
      std::fputs(line, stdout);
    }
    if (!manifest) throw std::runtime_error("cannot write " + out_dir + "/variants.txt");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ims-variants: %s\n", e.what());
    return 1;
  }
  return 0;
}

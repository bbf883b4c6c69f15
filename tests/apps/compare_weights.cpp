// simpli_compare_weights A B TOLERANCE [differ]: compares two weight files (safetensors, the same
// keys and shapes) value by value and prints the largest absolute difference and where it is.
// Exit 0 when every difference is <= TOLERANCE (with "differ": when some difference is larger,
// the negative control of a comparison), 1 otherwise, 2 on bad input.
#include "simpli/error.h"
#include "simpli/model/io/safetensors.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) {
  if (argc < 4 || argc > 5 || (argc == 5 && std::string(argv[4]) != "differ")) {
    std::fprintf(stderr, "usage: simpli_compare_weights A B TOLERANCE [differ]\n");
    return 2;
  }
  try {
    const simpli::io::SafeTensorsReader a(argv[1]), b(argv[2]);
    const double tolerance = std::atof(argv[3]);
    if (a.keys() != b.keys())
      simpli::fail(argv[1], " and ", argv[2], " hold different keys");
    double worst = 0;
    std::string where;
    std::size_t values = 0;
    for (const std::string& key : a.keys()) {
      const auto x = a.readF64(key), y = b.readF64(key);
      if (x.shape != y.shape)
        simpli::fail("key '", key, "': shapes differ");
      for (std::size_t i = 0; i < x.data.size(); ++i) {
        const double d = std::abs(x.data[i] - y.data[i]);
        if (!(d <= worst)) { // NaN counts as the worst
          worst = std::isnan(d) ? INFINITY : d;
          where = key + "[" + std::to_string(i) + "]";
        }
      }
      values += x.data.size();
    }
    std::printf("%zu values in %zu tensors; largest difference %.3g at %s (tolerance %.3g)\n",
                values, a.keys().size(), worst, where.empty() ? "-" : where.c_str(), tolerance);
    const bool within = worst <= tolerance;
    if (argc == 5) {
      std::printf(within ? "FAIL: the files agree within the tolerance\n" : "differ: yes\n");
      return within ? 1 : 0;
    }
    if (!within)
      std::printf("FAIL: difference above the tolerance\n");
    return within ? 0 : 1;
  } catch (const simpli::Error& e) {
    std::fprintf(stderr, "simpli_compare_weights: %s\n", e.what());
    return 2;
  }
}

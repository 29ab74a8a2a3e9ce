// The heap on transparent huge pages (src/app/heap_pages.hpp): the range it marks, that later
// allocations land in it, and that a run gives the same output with and without it.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "heap_pages.hpp"
#include "process.hpp"

namespace {

using traverse::testing::scratch;

/// The VmFlags and AnonHugePages of the mapping holding address a (/proc/self/smaps).
struct Mapping {
  bool found = false;
  std::string flags;
  long anon_huge_kb = -1;
};
Mapping mapping_of(std::uintptr_t a) {
  std::ifstream in("/proc/self/smaps");
  Mapping m;
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    unsigned long lo = 0, hi = 0;
    if (std::sscanf(line.c_str(), "%lx-%lx ", &lo, &hi) == 2 && line.find(':') > line.find(' ')) {
      if (inside) break;
      inside = a >= lo && a < hi;
      m.found = m.found || inside;
      continue;
    }
    if (!inside) continue;
    if (line.rfind("VmFlags:", 0) == 0) m.flags = line.substr(8);
    if (line.rfind("AnonHugePages:", 0) == 0) m.anon_huge_kb = std::atol(line.c_str() + 14);
  }
  return m;
}

std::string thp_mode() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string s;
  std::getline(in, s);
  return s;
}

// The marked range holds whole 2 MiB pages, at least the bytes asked for; the allocations
// that follow come from it (the next one starts a chunk header past its first boundary);
// its mapping carries the huge-page flag (hg), and memory written there reads back.
TEST(HeapPages, LaterAllocationsComeFromTheMarkedRange) {
  const std::size_t bytes = std::size_t{8} << 20, huge = std::size_t{2} << 20;
  const std::size_t marked = traverse::app::set_up_heap(bytes);  // as traverse's main does
  auto* p = static_cast<unsigned char*>(std::malloc(std::size_t{3} << 20));  // before anything else allocates
  const std::string mode = thp_mode();
  std::printf("transparent huge pages: %s; marked %zu bytes\n", mode.empty() ? "(not in this kernel)" : mode.c_str(),
              marked);
  if (marked == 0) std::free(p);
  if (marked == 0) GTEST_SKIP() << "the kernel refused MADV_HUGEPAGE (no transparent huge pages: " << mode << ")";
  EXPECT_GE(marked, bytes);
  EXPECT_EQ(marked % huge, 0u);
  ASSERT_NE(p, nullptr);
  const auto a = reinterpret_cast<std::uintptr_t>(p);
  EXPECT_EQ((a + 16) % huge, 0u) << "the first allocation after it starts right at the boundary";
  for (std::size_t i = 0; i < (std::size_t{3} << 20); i += 4096) p[i] = static_cast<unsigned char>(i / 4096);
  long sum = 0;
  for (std::size_t i = 0; i < (std::size_t{3} << 20); i += 4096) sum += p[i];
  long expect = 0;
  for (std::size_t k = 0; k < 768; ++k) expect += static_cast<unsigned char>(k);
  EXPECT_EQ(sum, expect);
  const Mapping m = mapping_of(a + 16);
  ASSERT_TRUE(m.found);
  EXPECT_NE(m.flags.find(" hg"), std::string::npos) << m.flags;
  std::printf("its mapping: AnonHugePages %ld kB after 3 MiB written (VmFlags%s)\n", m.anon_huge_kb, m.flags.c_str());
  std::free(p);
}

// The default scene with the heap on huge pages (the default) and on 4 KiB pages
// (TRAVERSE_HUGE_PAGES=0): the same output file, value for value.
TEST(HeapPages, ARunsOutputDoesNotDependOnThem) {
  const auto d = scratch("heap_pages");
  const std::string scene = std::string(TRAVERSE_SOURCE_DIR) + "/inputs/default.yaml";
  const std::string a = (d / "huge.h5").string(), b = (d / "small.h5").string();
  const auto ra = traverse::testing::run_command(std::string(TRAVERSE_EXE) + " run " + scene + " -o " + a +
                                                 " --overwrite -q --set output.fields=[r,R,u,omega,kappa,n,m]");
  ASSERT_EQ(ra.code, 0) << ra.out;
  ASSERT_EQ(setenv("TRAVERSE_HUGE_PAGES", "0", 1), 0);
  const auto rb = traverse::testing::run_command(std::string(TRAVERSE_EXE) + " run " + scene + " -o " + b +
                                                 " --overwrite -q --set output.fields=[r,R,u,omega,kappa,n,m]");
  unsetenv("TRAVERSE_HUGE_PAGES");
  ASSERT_EQ(rb.code, 0) << rb.out;
  std::string why;
  const double diff = traverse::testing::max_file_difference(a, b, why);
  EXPECT_EQ(diff, 0.0) << why;
}

}  // namespace

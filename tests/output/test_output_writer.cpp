// Output module, run on 1 and 2 ranks: HDF5 round trip (exact values), refusals, status
// transitions, crash-safety ordering and the XDMF sidecar.
#include <gtest/gtest.h>
#include <mpi.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "sample_run.hpp"
#include "traverse/output/reader.hpp"
#include "traverse/output/sidecar.hpp"
#include "traverse/output/writer.hpp"
#include "xdmf_check.hpp"

using namespace traverse::output;
namespace fs = std::filesystem;

namespace {

int rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}
int size() {
  int s = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &s);
  return s;
}

/// A fresh scratch folder per test and rank count, identical on all ranks.
std::string scratch(const std::string& test) {
  const fs::path dir = fs::path(TRAVERSE_BINARY_DIR) / "tests" / "output" / "scratch" /
                       (test + "_np" + std::to_string(size()));
  if (rank() == 0) {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  return dir.string();
}

/// Runs `f` expecting an OutputError on every rank; returns its message.
template <typename F>
std::string expect_output_error(F f) {
  std::string msg;
  try {
    f();
  } catch (const OutputError& e) {
    msg = e.what();
  }
  int got = msg.empty() ? 0 : 1, all = 0;
  MPI_Allreduce(&got, &all, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(all, size()) << "every rank must throw OutputError";
  return msg;
}

}  // namespace

TEST(OutputWriter, RoundTripExact) {
  const std::string path = scratch("roundtrip") + "/run.h5";
  const NodeLayout l = sample::layout(MPI_COMM_WORLD);
  const std::size_t steps = 5;
  {
    Writer w(MPI_COMM_WORLD, path, false, sample::run_info(), l, sample::loads);
    sample::declare(w);
    for (std::size_t k = 0; k < steps; ++k) {
      sample::write_step(w, l, k);
      if (k == 2) sample::write_restart(w, l, k);
    }
    sample::write_restart(w, l, steps - 1);  // overwrites the first restart
    w.finish();
    EXPECT_EQ(w.steps_written(), steps);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  // Every rank reads the file independently (serial reader).
  Reader r(path);
  EXPECT_EQ(r.steps_written(), steps);
  EXPECT_EQ(r.status(), "complete");
  const RunInfo info = sample::run_info();
  EXPECT_EQ(r.attribute("traverse_version"), info.version);
  EXPECT_EQ(r.attribute("command_line"), info.command_line);
  EXPECT_EQ(r.attribute("scene"), info.scene_text);
  EXPECT_EQ(r.attribute("scene_file"), info.scene_file);
  EXPECT_EQ(r.attribute("model"), "rod");
  EXPECT_EQ(r.node_count(), sample::nodes);
  EXPECT_EQ(r.moving_loads(), sample::loads);

  std::size_t mismatches = 0, compared = 0;
  auto same = [&](double a, double b) {
    ++compared;
    if (a != b) ++mismatches;
  };
  const auto s = r.arclength();
  ASSERT_EQ(s.size(), sample::nodes);
  for (std::size_t i = 0; i < sample::nodes; ++i) same(s[i], sample::s(i));
  const auto t = r.time();
  ASSERT_EQ(t.size(), steps);
  const Series sig = r.sigma();
  ASSERT_EQ(sig.rows, steps);
  ASSERT_EQ(sig.components, sample::loads);
  EXPECT_EQ(sig.units, "m");
  for (std::size_t k = 0; k < steps; ++k) {
    same(t[k], sample::time(k));
    for (std::size_t j = 0; j < sample::loads; ++j) same(sig.values[k * sample::loads + j], sample::sigma(k, j));
  }
  const auto probes = r.probe_names();
  ASSERT_EQ(probes, (std::vector<std::string>{"midspan_w", "reaction"}));
  const char* probe_names[2] = {"midspan_w", "reaction"};
  for (std::size_t p = 0; p < 2; ++p) {
    const Series ps = r.probe(probe_names[p]);
    ASSERT_EQ(ps.rows, steps);
    ASSERT_EQ(ps.components, sample::probe_components[p]);
    for (std::size_t k = 0; k < steps; ++k)
      for (std::size_t c = 0; c < ps.components; ++c)
        same(ps.values[k * ps.components + c], sample::probe(p, k, c));
  }
  const Series reaction = r.probe("reaction");
  EXPECT_EQ(reaction.units, "N");
  EXPECT_EQ(reaction.description, "support reaction force");
  EXPECT_EQ(reaction.component_names, (std::vector<std::string>{"x", "y", "z"}));
  EXPECT_TRUE(r.probe("midspan_w").component_names.empty());

  const char* field_names[3] = {"w", "r", "strain"};
  for (std::size_t f = 0; f < 3; ++f) {
    const Series info_f = r.field_info(field_names[f]);
    ASSERT_EQ(info_f.components, sample::field_components[f]);
    ASSERT_EQ(info_f.rows, sample::nodes);
    ASSERT_EQ(info_f.component_names.size(), info_f.components);
    for (std::size_t k = 0; k < steps; ++k) {
      const auto v = r.field(field_names[f], k);
      ASSERT_EQ(v.size(), sample::nodes * info_f.components);
      for (std::size_t i = 0; i < sample::nodes; ++i)
        for (std::size_t c = 0; c < info_f.components; ++c)
          same(v[i * info_f.components + c], sample::field(f, k, i, c));
    }
  }
  // A rank's own range, as a restart would read it.
  const auto mine = r.field("strain", 3, l.first, l.count);
  ASSERT_EQ(mine.size(), l.count * 6);
  for (std::size_t i = 0; i < l.count; ++i) same(mine[i * 6 + 5], sample::field(2, 3, l.first + i, 5));
  EXPECT_EQ(r.field_info("strain").component_names[3], "k1");
  EXPECT_EQ(r.field_info("w").component_names, (std::vector<std::string>{"0"}));
  EXPECT_THROW(r.field("w", steps), OutputError);

  // Restart: the last write replaced the first.
  ASSERT_TRUE(r.has_restart());
  EXPECT_EQ(r.restart_time(), sample::time(steps - 1));
  EXPECT_EQ(r.restart_step(), steps);
  EXPECT_EQ(r.restart_names(), (std::vector<std::string>{"loads", "state"}));
  const Series st = r.restart("state");
  ASSERT_EQ(st.rows, sample::nodes);
  ASSERT_EQ(st.components, 2u);
  for (std::size_t i = 0; i < sample::nodes; ++i)
    for (std::size_t c = 0; c < 2; ++c)
      same(st.values[i * 2 + c], static_cast<double>(i) + 0.5 * static_cast<double>(c) +
                                     static_cast<double>(steps - 1));
  const Series st_mine = r.restart("state", l.first, l.count);
  ASSERT_EQ(st_mine.rows, l.count);
  const Series ld = r.restart("loads");
  ASSERT_EQ(ld.values, (std::vector<double>{1.5, 2.5, static_cast<double>(steps - 1)}));

  EXPECT_EQ(mismatches, 0u);
  std::printf("[rank %d/%d] round trip: %zu values compared, %zu mismatches\n", rank(), size(),
              compared, mismatches);
}

TEST(OutputWriter, XdmfSidecarIsWellFormed) {
  const std::string dir = scratch("xdmf");
  const NodeLayout l = sample::layout(MPI_COMM_WORLD);
  const std::string path = dir + "/run.h5";
  {
    Writer w(MPI_COMM_WORLD, path, false, sample::run_info(), l, sample::loads);
    EXPECT_EQ(w.xdmf_path(), dir + "/run.xmf");
    sample::declare(w);
    for (std::size_t k = 0; k < 4; ++k) sample::write_step(w, l, k);
    w.finish();
  }
  // Beam-like run: no "r"; a designated geometry field, and one without any geometry.
  const std::string beam = dir + "/beam.h5", plain = dir + "/plain.h5";
  for (const std::string& p : {beam, plain}) {
    RunInfo info = sample::run_info();
    info.model = "beam";
    Writer w(MPI_COMM_WORLD, p, false, info, l, 1);
    w.add_field({"w", 1, "m", "deflection", {}, false});
    if (p == beam) w.add_field({"position", 3, "m", "(s, w, 0)", {"x", "y", "z"}, true});
    for (std::size_t k = 0; k < 3; ++k) {
      std::vector<double> wv, pos;
      for (std::size_t i = 0; i < l.count; ++i) {
        wv.push_back(0.5 * static_cast<double>(k) + 0.0625 * static_cast<double>(l.first + i));
        pos.insert(pos.end(), {l.s[i], wv.back(), 0.0});
      }
      // The load moves along the beam: 0.1 m per step.
      if (p == beam) w.write_step(sample::time(k), {0.1 * static_cast<double>(k)}, {}, {wv, pos});
      else w.write_step(sample::time(k), {0.1 * static_cast<double>(k)}, {}, {wv});
    }
    w.finish();
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank() != 0) return;
  const auto rep = test::check_xdmf(dir + "/run.xmf", path);
  for (const auto& p : rep.problems) ADD_FAILURE() << p;
  EXPECT_EQ(rep.grids, 4u);
  // Per grid: segments + geometry (r) + s + w + r + 6 strain scalars = 11 HDF items, 9 of them views.
  EXPECT_EQ(rep.hdf_items, 4u * 11u);
  EXPECT_EQ(rep.views, 4u * 9u);
  // The sample's second load is off the structure at s = 10 m: both loads are drawn (extrapolated).
  EXPECT_EQ(rep.load_grids, 4u);
  const std::string run_xmf = test::slurp(dir + "/run.xmf");
  EXPECT_NE(run_xmf.find("Name=\"strain_k2\""), std::string::npos);
  EXPECT_NE(run_xmf.find("AttributeType=\"Vector\""), std::string::npos);
  EXPECT_NE(run_xmf.find("Name=\"s\" AttributeType=\"Scalar\""), std::string::npos);
  EXPECT_NE(run_xmf.find("<Time Value=\"0.75\"/>"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir + "/run.xmf.tmp"));
  std::printf("run.xmf: %zu grids, %zu HDF items (%zu views), %zu load grids, %zu problems\n", rep.grids,
              rep.hdf_items, rep.views, rep.load_grids, rep.problems.size());
  // Every view holds exactly its step of the field.
  std::size_t mismatches = 0, compared = 0;
  for (std::size_t k = 0; k < 4; ++k) {
    const auto r = test::read_doubles(path, "/xdmf/r/" + std::to_string(k));
    const auto k2 = test::read_doubles(path, "/xdmf/strain_k2/" + std::to_string(k));
    ASSERT_EQ(r.size(), 3 * sample::nodes);
    ASSERT_EQ(k2.size(), sample::nodes);
    for (std::size_t i = 0; i < sample::nodes; ++i) {
      for (std::size_t c = 0; c < 3; ++c, ++compared) mismatches += r[3 * i + c] != sample::field(1, k, i, c);
      ++compared;
      mismatches += k2[i] != sample::field(2, k, i, 4);
    }
  }
  EXPECT_EQ(mismatches, 0u) << compared << " view values compared";
  // `traverse xdmf` (write_sidecar) rebuilds the same text from the file alone.
  const SidecarResult again = write_sidecar(path, dir + "/again.xmf");
  EXPECT_EQ(again.steps, 4u);
  EXPECT_EQ(again.views_created, 0u);
  EXPECT_EQ(test::slurp(dir + "/again.xmf"), run_xmf);

  // A file without views (as older traverse versions wrote them): write_sidecar adds them.
  {
    const std::string old = dir + "/old.h5";
    fs::copy_file(path, old);
    hid_t f = H5Fopen(old.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    EXPECT_GE(H5Ldelete(f, "/xdmf", H5P_DEFAULT), 0);
    H5Fclose(f);
    const SidecarResult added = write_sidecar(old);
    EXPECT_EQ(added.views_created, 4u * 8u);  // w, r and 6 strain components per step
    const auto ro = test::check_xdmf(dir + "/old.xmf", old);
    for (const auto& p : ro.problems) ADD_FAILURE() << "old file: " << p;
    EXPECT_EQ(ro.grids, 4u);
    const auto k1 = test::read_doubles(old, "/xdmf/strain_k1/3");
    ASSERT_EQ(k1.size(), sample::nodes);
    EXPECT_EQ(k1[6], sample::field(2, 3, 6, 3));
    EXPECT_EQ(write_sidecar(old).views_created, 0u);  // now complete
  }

  const auto rb = test::check_xdmf(dir + "/beam.xmf", beam);
  for (const auto& p : rb.problems) ADD_FAILURE() << p;
  EXPECT_EQ(rb.grids, 3u);
  const std::string beam_xmf = test::slurp(dir + "/beam.xmf");
  const std::string beam_h5 = std::filesystem::absolute(dir + "/beam.h5").lexically_normal().string();
  EXPECT_NE(beam_xmf.find("<Geometry GeometryType=\"XYZ\"><DataItem Dimensions=\"7 3\" DataType=\"Float\" "
                          "Precision=\"8\" Format=\"HDF\">" + beam_h5 + ":/xdmf/position/2</DataItem></Geometry>"),
            std::string::npos);
  // The load at sigma = 0.2 m sits between nodes 1 (s = 0.125) and 2 (s = 0.25) of the
  // deflected beam: x = 0.2, w interpolated linearly.
  const double xi = (0.2 - sample::s(1)) / (sample::s(2) - sample::s(1));
  const double x_load = (1.0 - xi) * sample::s(1) + xi * sample::s(2);
  const double w_load = (1.0 - xi) * (1.0 + 0.0625) + xi * (1.0 + 0.125);
  EXPECT_NEAR(x_load, 0.2, 1e-15);
  EXPECT_NEAR(w_load, 1.1, 1e-15);
  char want[128];
  std::snprintf(want, sizeof want, "Format=\"XML\">%.17g %.17g 0</DataItem></Geometry>", x_load, w_load);
  EXPECT_NE(beam_xmf.find(want), std::string::npos) << "expected " << want;
  EXPECT_EQ(test::slurp(dir + "/beam.xmf"), (write_sidecar(beam, dir + "/beam_again.xmf"), test::slurp(dir + "/beam_again.xmf")));
  const auto rp = test::check_xdmf(dir + "/plain.xmf", plain);
  for (const auto& p : rp.problems) ADD_FAILURE() << p;
  EXPECT_NE(test::slurp(dir + "/plain.xmf").find(":/mesh/position</DataItem>"), std::string::npos);
  // A beam's reference positions lie along x.
  const auto ref = test::read_doubles(plain, "/mesh/position");
  ASSERT_EQ(ref.size(), 3 * sample::nodes);
  EXPECT_EQ(ref[3 * 6 + 0], sample::s(6));
  EXPECT_EQ(ref[3 * 6 + 2], 0.0);
  Reader r(plain);
  EXPECT_EQ(r.arclength().size(), sample::nodes);
}

// A sidecar longer than the 64 KiB pieces it is written in (300 steps, about 1 kB each): the
// pieces join into a well-formed document that names every view, and `traverse xdmf` rebuilds
// it identically; every view (contiguous copies) holds its step of the field.
TEST(OutputWriter, LongSidecarIsWrittenInPieces) {
  const std::string dir = scratch("xdmf-long");
  const NodeLayout l = sample::layout(MPI_COMM_WORLD);
  const std::string path = dir + "/run.h5";
  const std::size_t steps = 300;
  {
    Writer w(MPI_COMM_WORLD, path, false, sample::run_info(), l, sample::loads);
    sample::declare(w);
    for (std::size_t k = 0; k < steps; ++k) sample::write_step(w, l, k);
    w.finish();
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank() != 0) return;
  const std::string xmf = test::slurp(dir + "/run.xmf");
  EXPECT_GT(xmf.size(), 3u * 65536u);
  const auto rep = test::check_xdmf(dir + "/run.xmf", path);
  for (const auto& p : rep.problems) ADD_FAILURE() << p;
  EXPECT_EQ(rep.grids, steps);
  EXPECT_EQ(rep.views, steps * 9u);
  const SidecarResult again = write_sidecar(path, dir + "/again.xmf");
  EXPECT_EQ(again.steps, steps);
  EXPECT_EQ(test::slurp(dir + "/again.xmf"), xmf);
  for (const std::size_t k : {std::size_t(0), std::size_t(150), steps - 1}) {
    const auto r = test::read_doubles(path, "/xdmf/r/" + std::to_string(k));
    ASSERT_EQ(r.size(), 3 * sample::nodes);
    for (std::size_t i = 0; i < sample::nodes; ++i)
      for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(r[3 * i + c], sample::field(1, k, i, c)) << k << " " << i;
  }
}

TEST(OutputWriter, RefusesToOverwrite) {
  const std::string dir = scratch("overwrite");
  const NodeLayout l = sample::layout(MPI_COMM_WORLD);
  const std::string path = dir + "/run.h5";
  {
    Writer w(MPI_COMM_WORLD, path, false, sample::run_info(), l, 1);
    w.write_step(1.0, {0.0}, {}, {});
    w.finish();
  }
  const std::string msg = expect_output_error(
      [&] { Writer w(MPI_COMM_WORLD, path, false, sample::run_info(), l, 1); });
  std::printf("[rank %d] refusal: %s\n", rank(), msg.c_str());
  EXPECT_NE(msg.find(path), std::string::npos);
  EXPECT_NE(msg.find("--overwrite"), std::string::npos);
  {
    Reader r(path);  // untouched
    EXPECT_EQ(r.steps_written(), 1u);
    EXPECT_EQ(r.status(), "complete");
  }
  MPI_Barrier(MPI_COMM_WORLD);
  {
    Writer w(MPI_COMM_WORLD, path, true, sample::run_info(), l, 1);
    w.finish();
  }
  Reader r(path);
  EXPECT_EQ(r.steps_written(), 0u);
  EXPECT_EQ(r.time().size(), 0u);
  MPI_Barrier(MPI_COMM_WORLD);

  // A lone sidecar is protected too.
  const std::string other = dir + "/other.h5";
  if (rank() == 0) std::ofstream(dir + "/other.xmf") << "<Xdmf/>\n";
  MPI_Barrier(MPI_COMM_WORLD);
  const std::string msg2 = expect_output_error(
      [&] { Writer w(MPI_COMM_WORLD, other, false, sample::run_info(), l, 1); });
  EXPECT_NE(msg2.find("other.xmf"), std::string::npos) << msg2;
  EXPECT_FALSE(fs::exists(other));
}

TEST(OutputWriter, MissingFolder) {
  const std::string dir = scratch("missing");
  const NodeLayout l = sample::layout(MPI_COMM_WORLD);
  const std::string path = dir + "/no/such/folder/run.h5";
  const std::string msg = expect_output_error(
      [&] { Writer w(MPI_COMM_WORLD, path, true, sample::run_info(), l, 1); });
  std::printf("[rank %d] missing folder: %s\n", rank(), msg.c_str());
  EXPECT_NE(msg.find("does not exist"), std::string::npos);
  EXPECT_NE(msg.find(dir + "/no/such/folder"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir + "/no"));
}

TEST(OutputWriter, UnwritableFolder) {
  // The tests run as root, for whom chmod a-w does not block writes. A folder that cannot be
  // written even by root is one that is not a folder: the parent is a regular file.
  const std::string dir = scratch("unwritable");
  const NodeLayout l = sample::layout(MPI_COMM_WORLD);
  if (rank() == 0) std::ofstream(dir + "/plainfile") << "not a folder\n";
  MPI_Barrier(MPI_COMM_WORLD);
  const std::string path = dir + "/plainfile/run.h5";
  const std::string msg = expect_output_error(
      [&] { Writer w(MPI_COMM_WORLD, path, true, sample::run_info(), l, 1); });
  std::printf("[rank %d] unwritable folder: %s\n", rank(), msg.c_str());
  EXPECT_NE(msg.find("not a folder"), std::string::npos);
  // A deeper path under the file (ENOTDIR from stat).
  const std::string msg2 = expect_output_error([&] {
    Writer w(MPI_COMM_WORLD, dir + "/plainfile/sub/run.h5", true, sample::run_info(), l, 1);
  });
  EXPECT_NE(msg2.find("not a folder"), std::string::npos) << msg2;
  if (geteuid() != 0) {  // as an ordinary user, a read-only folder is refused too
    if (rank() == 0) fs::create_directory(dir + "/ro"), fs::permissions(dir + "/ro", fs::perms::owner_read | fs::perms::owner_exec);
    MPI_Barrier(MPI_COMM_WORLD);
    const std::string msg3 = expect_output_error(
        [&] { Writer w(MPI_COMM_WORLD, dir + "/ro/run.h5", true, sample::run_info(), l, 1); });
    EXPECT_NE(msg3.find("not writable"), std::string::npos) << msg3;
  }
}

TEST(OutputWriter, StatusTransitionsAndStepOrdering) {
  const std::string dir = scratch("status");
  const NodeLayout l = sample::layout(MPI_COMM_WORLD);
  const std::string ok = dir + "/ok.h5", bad = dir + "/bad.h5", dropped = dir + "/dropped.h5";
  // The file is read (rank 0, serial reader) while the writer still has it open: what a
  // reader sees after each step is what a crash at that moment would leave.
  auto peek = [](const std::string& p, const std::string& want_status, std::size_t want_steps) {
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank() == 0) {
      Reader r(p);
      EXPECT_EQ(r.status(), want_status);
      EXPECT_EQ(r.steps_written(), want_steps);
      EXPECT_EQ(r.time().size(), want_steps);
    }
    MPI_Barrier(MPI_COMM_WORLD);
  };
  {
    Writer w(MPI_COMM_WORLD, ok, false, sample::run_info(), l, sample::loads);
    w.set_intervals(3600.0, 3600.0);  // no timed flush during the test: only explicit ones
    sample::declare(w);
    peek(ok, "running", 0);
    for (std::size_t k = 0; k < 3; ++k) {
      sample::write_step(w, l, k);
      // Kept in memory: the file still shows the steps before.
      peek(ok, "running", k);
      EXPECT_EQ(w.steps_written(), k + 1);
      EXPECT_EQ(w.steps_flushed(), k);
      w.flush();
      peek(ok, "running", k + 1);
      EXPECT_EQ(w.steps_flushed(), k + 1);
    }
    sample::write_step(w, l, 3);
    sample::write_step(w, l, 4);
    peek(ok, "running", 3);
    // The sidecar is not rewritten by flushes within its interval: still the empty one.
    if (rank() == 0) {
      EXPECT_EQ(test::check_xdmf(dir + "/ok.xmf", ok).grids, 0u);
    }
    w.finish();  // flushes the kept steps, writes the sidecar
    peek(ok, "complete", 5);
    if (rank() == 0) {
      EXPECT_EQ(test::check_xdmf(dir + "/ok.xmf", ok).grids, 5u);
    }
    EXPECT_THROW(sample::write_step(w, l, 5), OutputError);
  }
  {
    // Interval 0: every step is flushed and announced at once.
    Writer w(MPI_COMM_WORLD, bad, false, sample::run_info(), l, sample::loads);
    w.set_intervals(0.0, 3600.0);
    sample::declare(w);
    sample::write_step(w, l, 0);
    peek(bad, "running", 1);
    w.fail("Newton iteration diverged at t = 0.25 s");
    peek(bad, "failed: Newton iteration diverged at t = 0.25 s", 1);
  }
  {
    // Both intervals 0: every step is flushed and the sidecar describes it at once.
    Writer w(MPI_COMM_WORLD, dir + "/eager.h5", false, sample::run_info(), l, sample::loads);
    w.set_intervals(0.0, 0.0);
    sample::declare(w);
    for (std::size_t k = 0; k < 3; ++k) {
      sample::write_step(w, l, k);
      peek(dir + "/eager.h5", "running", k + 1);
      if (rank() == 0) {
        EXPECT_EQ(test::check_xdmf(dir + "/eager.xmf", dir + "/eager.h5").grids, k + 1);
      }
    }
    w.finish();
  }
  {
    // Destroyed with kept steps (e.g. by an exception): they are flushed, the status says why.
    Writer w(MPI_COMM_WORLD, dropped, false, sample::run_info(), l, sample::loads);
    w.set_intervals(3600.0, 3600.0);
    sample::declare(w);
    sample::write_step(w, l, 0);
    sample::write_step(w, l, 1);
  }
  peek(dropped, "failed: output closed before finish() or fail()", 2);
  peek(bad, "failed: Newton iteration diverged at t = 0.25 s", 1);
}

TEST(OutputWriter, MisuseIsReportedOnAllRanks) {
  const std::string dir = scratch("misuse");
  const NodeLayout l = sample::layout(MPI_COMM_WORLD);
  Writer w(MPI_COMM_WORLD, dir + "/run.h5", false, sample::run_info(), l, sample::loads);
  sample::declare(w);
  EXPECT_NE(expect_output_error([&] { w.add_probe({"midspan_w", 1, "m", "dup", {}}); }).find("duplicate"),
            std::string::npos);
  EXPECT_NE(expect_output_error([&] { w.add_field({"bad/name", 1, "m", "", {}, false}); }).find("invalid"),
            std::string::npos);
  EXPECT_NE(expect_output_error([&] { w.add_field({"g", 2, "m", "", {}, true}); }).find("3 components"),
            std::string::npos);
  // Wrong local field size on the last rank only: every rank throws the same message.
  std::vector<double> w0(l.count), r0(l.count * 3), s0(l.count * 6 + (rank() == size() - 1 ? 1 : 0));
  const std::string msg = expect_output_error(
      [&] { w.write_step(0.0, {0.0, 1.0}, {{0.0}, {0.0, 0.0, 0.0}}, {w0, r0, s0}); });
  EXPECT_NE(msg.find("rank " + std::to_string(size() - 1)), std::string::npos) << msg;
  EXPECT_EQ(w.steps_written(), 0u);
  sample::write_step(w, l, 0);  // still usable
  EXPECT_THROW(w.add_probe({"late", 1, "m", "", {}}), OutputError);
  w.finish();
}

TEST(OutputReader, ErrorsNameTheHdf5Call) {
  const std::string dir = scratch("reader_errors");
  const std::string not_h5 = dir + "/not_hdf5.h5";
  if (rank() == 0) std::ofstream(not_h5) << "plain text\n";
  MPI_Barrier(MPI_COMM_WORLD);
  for (const std::string& p : {dir + "/absent.h5", not_h5}) {
    std::string msg;
    try {
      Reader r(p);
    } catch (const OutputError& e) {
      msg = e.what();
    }
    std::printf("[rank %d] reader error: %s\n", rank(), msg.c_str());
    EXPECT_NE(msg.find("H5Fopen"), std::string::npos) << msg;
    EXPECT_NE(msg.find(p), std::string::npos) << msg;
  }
}

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  int rc = RUN_ALL_TESTS();
  int worst = 0;
  MPI_Allreduce(&rc, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return worst;
}

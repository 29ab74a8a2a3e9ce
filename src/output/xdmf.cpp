#include "xdmf.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>

#include "traverse/output/output_error.hpp"

namespace traverse::output::detail {

namespace {

std::string xml_escape(const std::string& in) {
  std::string out;
  out.reserve(in.size());
  for (const char c : in) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c; break;
    }
  }
  return out;
}

void number(std::string& o, double v) {
  char buf[32];
  // + 0.0 turns -0 into 0: the Writer's values pass an MPI sum, the tool's do not.
  std::snprintf(buf, sizeof buf, "%.17g", v + 0.0);
  o += buf;
}

void count(std::string& o, std::size_t v) { o += std::to_string(v); }

void hdf_item(std::string& o, const std::string& dims, const char* type, int precision, const std::string& h5,
              const std::string& dataset) {
  o += "<DataItem Dimensions=\"";
  o += dims;
  o += "\" DataType=\"";
  o += type;
  o += "\" Precision=\"";
  o += std::to_string(precision);
  o += "\" Format=\"HDF\">";
  o += h5;
  o += ':';
  o += dataset;
  o += "</DataItem>";
}

}  // namespace

std::string sidecar_h5_name(const std::string& h5_path) {
  return std::filesystem::absolute(h5_path).lexically_normal().string();
}

XdmfPlan plan_views(const std::vector<XdmfFieldInfo>& fields) {
  XdmfPlan plan;
  std::set<std::string> taken{"s"};
  auto add = [&](std::string array, std::size_t f, std::size_t first, std::size_t n) {
    if (taken.count(array) > 0) array = fields[f].name + "_" + array;
    while (taken.count(array) > 0) array += "_";
    taken.insert(array);
    plan.views.push_back({array, f, first, n});
  };
  // Whole fields first, so that a field keeps its own name against a derived one.
  for (std::size_t f = 0; f < fields.size(); ++f)
    if ((fields[f].sidecar || fields[f].geometry) && (fields[f].components == 1 || fields[f].components == 3))
      taken.insert(fields[f].name);
  for (std::size_t f = 0; f < fields.size(); ++f) {
    const XdmfFieldInfo& fi = fields[f];
    if (!fi.sidecar && !fi.geometry) continue;
    if (fi.components == 1 || fi.components == 3) {
      taken.erase(fi.name);
      add(fi.name, f, 0, fi.components);
      if (fi.components == 3 && (fi.geometry || (plan.geometry < 0 && fi.name == "r")))
        plan.geometry = static_cast<int>(plan.views.size() - 1);
      continue;
    }
    bool triples = fi.components % 3 == 0 && fi.component_names.size() == fi.components;
    for (std::size_t c = 0; triples && c < fi.components; c += 3) {
      const std::string& a = fi.component_names[c];
      const std::string p = a.empty() ? std::string() : a.substr(0, a.size() - 1);
      triples = !p.empty() && a == p + "x" && fi.component_names[c + 1] == p + "y" &&
                fi.component_names[c + 2] == p + "z";
    }
    if (triples) {
      for (std::size_t c = 0; c < fi.components; c += 3) {
        const std::string& a = fi.component_names[c];
        add(a.substr(0, a.size() - 1), f, c, 3);
      }
    } else {
      for (std::size_t c = 0; c < fi.components; ++c)
        add(fi.name + "_" + (c < fi.component_names.size() ? fi.component_names[c] : std::to_string(c)), f, c, 1);
    }
  }
  // A field marked geometry wins over "r", whatever the order.
  for (std::size_t v = 0; v < plan.views.size(); ++v)
    if (fields[plan.views[v].field].geometry && plan.views[v].count == 3) plan.geometry = static_cast<int>(v);
  return plan;
}

bool load_point(std::size_t global_nodes, std::size_t first, std::size_t n, const double* s, const double* values,
                std::size_t width, double sigma, double* out) {
  if (n == 0 || !std::isfinite(sigma)) return false;
  if (global_nodes == 1) {
    std::copy(values, values + width, out);
    return true;
  }
  if (n < 2) return false;
  // Segment j (local index) joins local nodes j and j+1; global index first + j.
  const std::size_t last_global_segment = global_nodes - 2;
  std::size_t j = static_cast<std::size_t>(std::upper_bound(s, s + n, sigma) - s);  // first s > sigma
  j = j == 0 ? 0 : j - 1;                                                         // s_j <= sigma
  if (j > n - 2) j = n - 2;
  const std::size_t g = first + j;
  const bool lower_ok = g == 0 || sigma >= s[j];
  const bool upper_ok = g == last_global_segment || sigma < s[j + 1];
  if (!lower_ok || !upper_ok) return false;
  const double xi = (sigma - s[j]) / (s[j + 1] - s[j]);
  for (std::size_t c = 0; c < width; ++c) out[c] = (1.0 - xi) * values[width * j + c] + xi * values[width * (j + 1) + c];
  return true;
}

namespace {

// The loads' temporal collection (a point per load at each output step), when every output
// step has every load on the structure; `pass_on(false)` after each step.
void write_loads_grid(const XdmfModel& m, std::string& o, const std::function<void(bool)>& pass_on) {
  const std::size_t steps = m.times.size();
  const std::size_t W = m.load_width();
  bool loads_grid = m.loads > 0 && steps > 0 && m.sigma.size() == steps * m.loads &&
                    m.load_values.size() == W * steps * m.loads;
  for (std::size_t i = 0; loads_grid && i < m.sigma.size(); ++i) loads_grid = std::isfinite(m.sigma[i]);
  if (!loads_grid) return;
  std::string vertices;
  for (std::size_t l = 0; l < m.loads; ++l) vertices += (l ? " " : "") + std::to_string(l);
  const std::string L = std::to_string(m.loads);
  auto xml_item = [&](const std::string& dims, std::size_t k, std::size_t offset, std::size_t count) {
    o += "<DataItem Dimensions=\"" + dims + "\" DataType=\"Float\" Precision=\"8\" Format=\"XML\">";
    for (std::size_t l = 0; l < m.loads; ++l)
      for (std::size_t c = 0; c < count; ++c) {
        if (l || c) o += ' ';
        number(o, m.load_values[W * (m.loads * k + l) + offset + c]);
      }
    o += "</DataItem>";
  };
  o += "    <Grid Name=\"loads\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < steps; ++k) {
    o += "      <Grid Name=\"loads_";
    count(o, k);
    o += "\" GridType=\"Uniform\">\n        <Time Value=\"";
    number(o, m.times[k]);
    o += "\"/>\n        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" + L +
         "\" NodesPerElement=\"1\"><DataItem Dimensions=\"" + L +
         "\" DataType=\"Int\" Precision=\"4\" Format=\"XML\">" + vertices + "</DataItem></Topology>\n";
    o += "        <Geometry GeometryType=\"XYZ\">";
    xml_item(L + " 3", k, 0, 3);
    o += "</Geometry>\n        <Attribute Name=\"s\" AttributeType=\"Scalar\" Center=\"Node\">"
         "<DataItem Dimensions=\"" + L + "\" DataType=\"Float\" Precision=\"8\" Format=\"XML\">";
    for (std::size_t l = 0; l < m.loads; ++l) {
      if (l) o += ' ';
      number(o, m.sigma[m.loads * k + l]);
    }
    o += "</DataItem></Attribute>\n";
    std::size_t offset = 3;
    for (const XdmfView& a : m.arrays) {
      o += "        <Attribute Name=\"" + xml_escape(a.array) + "\" AttributeType=\"" +
           (a.count == 3 ? "Vector" : "Scalar") + "\" Center=\"Node\">";
      xml_item(a.count == 3 ? L + " 3" : L, k, offset, a.count);
      o += "</Attribute>\n";
      offset += a.count;
    }
    o += "      </Grid>\n";
    pass_on(false);
  }
  o += "    </Grid>\n";
}

}  // namespace

void write_xdmf_document(const XdmfModel& m, std::ostream& out) {
  const std::string h5 = xml_escape(m.h5_name);
  const std::size_t steps = m.times.size();
  const std::size_t n = m.nodes;
  // The text goes out in pieces of about 64 KiB: a long run's sidecar is never one string.
  constexpr std::size_t piece = 65536;
  std::string o;
  o.reserve(piece + 4096 + 512 * m.arrays.size());
  auto pass_on = [&](bool last) {
    if (!last && o.size() < piece) return;
    out.write(o.data(), static_cast<std::streamsize>(o.size()));
    o.clear();
  };
  o += "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n";

  write_loads_grid(m, o, pass_on);

  const std::string N = std::to_string(n);
  std::string topology;
  if (n >= 2) {
    topology = "        <Topology TopologyType=\"Polyline\" NumberOfElements=\"" + std::to_string(n - 1) +
               "\" NodesPerElement=\"2\">";
    hdf_item(topology, std::to_string(n - 1) + " 2", "Int", 4, h5, "/mesh/segments");
    topology += "</Topology>\n";
  } else {
    topology = "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"1\" NodesPerElement=\"1\">"
               "<DataItem Dimensions=\"1\" DataType=\"Int\" Precision=\"4\" Format=\"XML\">0</DataItem></Topology>\n";
  }
  std::string s_attr = "        <Attribute Name=\"s\" AttributeType=\"Scalar\" Center=\"Node\">";
  hdf_item(s_attr, N, "Float", 8, h5, "/mesh/s");
  s_attr += "</Attribute>\n";
  std::vector<std::string> array_head, array_dims;
  for (const XdmfView& a : m.arrays) {
    array_head.push_back("        <Attribute Name=\"" + xml_escape(a.array) + "\" AttributeType=\"" +
                         (a.count == 3 ? "Vector" : "Scalar") + "\" Center=\"Node\">");
    array_dims.push_back(a.count == 3 ? N + " 3" : N);
  }
  o += "    <Grid Name=\"structure\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < steps; ++k) {
    const std::string step = std::to_string(k);
    o += "      <Grid Name=\"step_" + step + "\" GridType=\"Uniform\">\n        <Time Value=\"";
    number(o, m.times[k]);
    o += "\"/>\n";
    o += topology;
    o += "        <Geometry GeometryType=\"XYZ\">";
    if (m.geometry >= 0)
      hdf_item(o, N + " 3", "Float", 8, h5, "/xdmf/" + xml_escape(m.arrays[static_cast<std::size_t>(m.geometry)].array) + "/" + step);
    else
      hdf_item(o, N + " 3", "Float", 8, h5, "/mesh/position");
    o += "</Geometry>\n";
    o += s_attr;
    for (std::size_t a = 0; a < m.arrays.size(); ++a) {
      o += array_head[a];
      hdf_item(o, array_dims[a], "Float", 8, h5, "/xdmf/" + xml_escape(m.arrays[a].array) + "/" + step);
      o += "</Attribute>\n";
    }
    o += "      </Grid>\n";
    pass_on(false);
  }
  o += "    </Grid>\n  </Domain>\n</Xdmf>\n";
  pass_on(true);
}

void write_xdmf_file(const std::string& path, const XdmfModel& model) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw OutputError("cannot write XDMF sidecar " + tmp + ": " + std::strerror(errno));
    write_xdmf_document(model, out);
    out.flush();
    if (!out) throw OutputError("cannot write XDMF sidecar " + tmp + ": " + std::strerror(errno));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw OutputError("cannot rename " + tmp + " to " + path + ": " + std::strerror(errno));
}

}  // namespace traverse::output::detail

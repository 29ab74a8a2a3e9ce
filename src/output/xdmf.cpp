#include "xdmf.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

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

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// A hyperslab of one step of /fields/<name> (steps x nodes x components): all nodes,
// components [c0, c0 + nc).
void field_slab(std::ostringstream& o, const std::string& indent, const std::string& h5,
                const std::string& field, std::size_t steps, std::size_t step, std::size_t nodes,
                std::size_t comps, std::size_t c0, std::size_t nc) {
  const std::string dims = nc == 1 ? std::to_string(nodes) : std::to_string(nodes) + " " + std::to_string(nc);
  o << indent << "<DataItem ItemType=\"HyperSlab\" Dimensions=\"" << dims << "\">\n"
    << indent << "  <DataItem Dimensions=\"3 3\" Format=\"XML\">" << step << " 0 " << c0
    << " 1 1 1 1 " << nodes << " " << nc << "</DataItem>\n"
    << indent << "  <DataItem Dimensions=\"" << steps << " " << nodes << " " << comps
    << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5 << ":/fields/"
    << xml_escape(field) << "</DataItem>\n"
    << indent << "</DataItem>\n";
}

}  // namespace

std::string xdmf_document(const XdmfModel& m) {
  const std::string h5 = xml_escape(m.h5_name);
  const std::size_t steps = m.times.size();
  const std::size_t n = m.nodes;
  std::ostringstream o;
  o << "<?xml version=\"1.0\" ?>\n"
    << "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
    << "<Xdmf Version=\"2.0\">\n"
    << "  <Domain>\n"
    << "    <Grid Name=\"traverse\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < steps; ++k) {
    o << "      <Grid Name=\"step_" << k << "\" GridType=\"Uniform\">\n"
      << "        <Time Value=\"" << number(m.times[k]) << "\"/>\n";
    if (n >= 2 && m.geometry_field >= 0) {
      // ParaView's XDMF 2 reader caches a grid's points keyed by the text of the first
      // DataItem of its Topology and Geometry; a hyperslab Geometry has no such text and
      // makes it log an error. A (whole-array) hyperslab Topology switches the cache off
      // quietly; the points change at every step anyway.
      o << "        <Topology TopologyType=\"Polyline\" NumberOfElements=\"" << n - 1
        << "\" NodesPerElement=\"2\">\n"
        << "          <DataItem ItemType=\"HyperSlab\" Dimensions=\"" << n - 1 << " 2\">\n"
        << "            <DataItem Dimensions=\"3 2\" Format=\"XML\">0 0 1 1 " << n - 1
        << " 2</DataItem>\n"
        << "            <DataItem Dimensions=\"" << n - 1
        << " 2\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">" << h5
        << ":/mesh/segments</DataItem>\n"
        << "          </DataItem>\n"
        << "        </Topology>\n";
    } else if (n >= 2) {
      o << "        <Topology TopologyType=\"Polyline\" NumberOfElements=\"" << n - 1
        << "\" NodesPerElement=\"2\">\n"
        << "          <DataItem Dimensions=\"" << n - 1
        << " 2\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">" << h5
        << ":/mesh/segments</DataItem>\n"
        << "        </Topology>\n";
    } else {
      o << "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"1\" NodesPerElement=\"1\">\n"
        << "          <DataItem Dimensions=\"1\" NumberType=\"Int\" Precision=\"4\" Format=\"XML\">0</DataItem>\n"
        << "        </Topology>\n";
    }
    o << "        <Geometry GeometryType=\"XYZ\">\n";
    if (m.geometry_field >= 0) {
      const XdmfField& g = m.fields[static_cast<std::size_t>(m.geometry_field)];
      field_slab(o, "          ", h5, g.name, steps, k, n, g.components, 0, 3);
    } else {
      o << "          <DataItem Dimensions=\"" << n
        << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5
        << ":/mesh/position</DataItem>\n";
    }
    o << "        </Geometry>\n";
    for (const XdmfField& f : m.fields) {
      if (f.components == 1 || f.components == 3) {
        o << "        <Attribute Name=\"" << xml_escape(f.name) << "\" AttributeType=\""
          << (f.components == 1 ? "Scalar" : "Vector") << "\" Center=\"Node\">\n";
        field_slab(o, "          ", h5, f.name, steps, k, n, f.components, 0, f.components);
        o << "        </Attribute>\n";
      } else {
        // XDMF has no general n-vector attribute: one scalar per component, <name>_<component>.
        for (std::size_t c = 0; c < f.components; ++c) {
          const std::string cname =
              c < f.component_names.size() ? f.component_names[c] : std::to_string(c);
          o << "        <Attribute Name=\"" << xml_escape(f.name + "_" + cname)
            << "\" AttributeType=\"Scalar\" Center=\"Node\">\n";
          field_slab(o, "          ", h5, f.name, steps, k, n, f.components, c, 1);
          o << "        </Attribute>\n";
        }
      }
    }
    o << "      </Grid>\n";
  }
  o << "    </Grid>\n"
    << "  </Domain>\n"
    << "</Xdmf>\n";
  return o.str();
}

void replace_file(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw OutputError("cannot write XDMF sidecar " + tmp + ": " + std::strerror(errno));
    out << text;
    out.flush();
    if (!out) throw OutputError("cannot write XDMF sidecar " + tmp + ": " + std::strerror(errno));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw OutputError("cannot rename " + tmp + " to " + path + ": " + std::strerror(errno));
}

}  // namespace traverse::output::detail

/// @file xdmf.cpp
/// Implementation of common/xdmf.hpp (the header states the contract, and for physics the equations and sources).
#include "common/xdmf.hpp"

#include <filesystem>
#include <sstream>

#include "common/atomic_file.hpp"

namespace common {

namespace {
std::string xml_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

std::string dims(std::size_t n, std::size_t ncomp) {
  return ncomp == 1 ? std::to_string(n) : std::to_string(n) + " " + std::to_string(ncomp);
}

const char* attribute_type(std::size_t ncomp) {
  switch (ncomp) {
    case 1: return "Scalar";
    case 3: return "Vector";
    case 6: return "Tensor6";
    case 9: return "Tensor";
    default: return "Matrix";
  }
}

void write_grid(std::ostringstream& o, const XdmfGrid& g, const std::string& indent) {
  const std::string file = xml_escape(g.h5file);
  o << indent << "<Grid Name=\"" << xml_escape(g.name) << "\" GridType=\"Uniform\">\n";
  o << indent << " <Time Value=\"" << g.time << "\"/>\n";
  const bool lines = !g.connectivity_path.empty();
  const std::size_t cells = lines ? g.elements : g.count;
  if (lines) {
    o << indent << " <Topology TopologyType=\"Polyline\" NumberOfElements=\"" << g.elements
      << "\" NodesPerElement=\"2\">\n";
    o << indent << "  <DataItem Format=\"HDF\" NumberType=\"UInt\" Precision=\"8\" Dimensions=\""
      << dims(g.elements, 2) << "\">" << file << ":" << xml_escape(g.connectivity_path) << "</DataItem>\n";
    o << indent << " </Topology>\n";
  } else {
    o << indent << " <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << g.count
      << "\" NodesPerElement=\"1\"/>\n";
  }
  o << indent << " <Geometry GeometryType=\"XYZ\">\n";
  o << indent << "  <DataItem Format=\"HDF\" NumberType=\"Float\" Precision=\"8\" Dimensions=\""
    << dims(g.count, 3) << "\">" << file << ":" << xml_escape(g.position_path) << "</DataItem>\n";
  o << indent << " </Geometry>\n";
  for (const auto& a : g.attributes) {
    o << indent << " <Attribute Name=\"" << xml_escape(a.name) << "\" AttributeType=\""
      << attribute_type(a.ncomp) << "\" Center=\"" << a.center << "\">\n";
    o << indent << "  <DataItem Format=\"HDF\" NumberType=\"" << a.number_type << "\" Precision=\""
      << a.precision << "\" Dimensions=\"" << dims(a.center == "Cell" ? cells : g.count, a.ncomp) << "\">" << file << ":"
      << xml_escape(a.h5path) << "</DataItem>\n";
    o << indent << " </Attribute>\n";
  }
  o << indent << "</Grid>\n";
}
}  // namespace

std::string xdmf_text(const std::vector<XdmfGrid>& grids) {
  std::ostringstream o;
  o.precision(17);
  o << "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n";
  o << "<Xdmf Version=\"3.0\">\n <Domain>\n";
  if (grids.size() == 1) {
    write_grid(o, grids[0], "  ");
  } else {
    o << "  <Grid Name=\"series\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (const auto& g : grids) write_grid(o, g, "   ");
    o << "  </Grid>\n";
  }
  o << " </Domain>\n</Xdmf>\n";
  return o.str();
}

std::string xdmf_text_spatial(const std::string& name, const std::vector<XdmfGrid>& grids) {
  std::ostringstream o;
  o.precision(17);
  o << "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n";
  o << "<Xdmf Version=\"3.0\">\n <Domain>\n";
  o << "  <Grid Name=\"" << xml_escape(name) << "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n";
  for (const auto& g : grids) write_grid(o, g, "   ");
  o << "  </Grid>\n </Domain>\n</Xdmf>\n";
  return o.str();
}

void write_xdmf(const std::string& xmf_path, const std::vector<XdmfGrid>& grids) {
  write_text_atomic(xmf_path, xdmf_text(grids));
}

std::string xdmf_path_for(const std::string& h5_path) {
  std::filesystem::path p(h5_path);
  p.replace_extension(".xmf");
  return p.string();
}

}  // namespace common

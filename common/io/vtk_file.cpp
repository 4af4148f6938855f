#include "vtk_file.hpp"

#include <charconv>
#include <cmath>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/measurements.hpp"

namespace granstab {
namespace {

void put(std::string& out, double v) {
  char buf[32];
  // ParaView parses plain decimals; non-finite values would break the file.
  const auto res = std::to_chars(buf, buf + sizeof buf, std::isfinite(v) ? v : 0.0);
  out.append(buf, res.ptr);
  out += ' ';
}

void put(std::string& out, std::size_t v) {
  out += std::to_string(v);
  out += ' ';
}

void data_array(std::string& out, const char* type, const char* name, int components,
                const std::vector<double>& values) {
  out += "        <DataArray type=\"";
  out += type;
  out += "\" Name=\"";
  out += name;
  out += "\" NumberOfComponents=\"" + std::to_string(components) + "\" format=\"ascii\">\n";
  for (const double v : values) put(out, v);
  out += "\n        </DataArray>\n";
}

}  // namespace

std::string format_vtu(const Configuration& c) {
  const std::size_t n = c.disks.size();
  const auto loads = contact_loads(c);
  const NetForces net = net_forces(c, loads);
  std::vector<std::size_t> shown;  // force-carrying contacts
  for (std::size_t k = 0; k < loads.size(); ++k) {
    if (loads[k].carrying) shown.push_back(k);
  }
  const std::size_t points = n + 2 * shown.size();
  const std::size_t cells = n + shown.size();

  std::vector<double> xyz, radius(points, 0.0), velocity(3 * points, 0.0),
      velocity_total(3 * points, 0.0), spin(points, 0.0), force(3 * points, 0.0);
  xyz.reserve(3 * points);
  for (std::size_t i = 0; i < n; ++i) {
    xyz.insert(xyz.end(), {c.disks.x[i], c.disks.y[i], 0.0});
    radius[i] = c.disks.radius[i];
    velocity[3 * i] = c.disks.vx[i];
    velocity[3 * i + 1] = c.disks.vy[i];
    double ax = 0.0, ay = 0.0;
    if (c.cell.periodic()) {
      ax = c.cell.strain_rate(0) * c.disks.x[i];
      ay = c.cell.strain_rate(1) * c.disks.y[i];
    }
    velocity_total[3 * i] = c.disks.vx[i] + ax;
    velocity_total[3 * i + 1] = c.disks.vy[i] + ay;
    spin[i] = c.disks.omega[i];
    force[3 * i] = net.fx[i];
    force[3 * i + 1] = net.fy[i];
  }
  std::vector<double> kind(cells, 0.0), f_n(cells, 0.0), f_t(cells, 0.0), sliding(cells, 0.0),
      wall(cells, 0.0);
  for (std::size_t s = 0; s < shown.size(); ++s) {
    const ContactLoad& load = loads[shown[s]];
    const int i = c.contacts.i[shown[s]];
    const double x = c.disks.x[i], y = c.disks.y[i];
    xyz.insert(xyz.end(), {x, y, 0.0, x + load.frame.lx, y + load.frame.ly, 0.0});
    kind[n + s] = 1.0;
    f_n[n + s] = load.f_n;
    f_t[n + s] = load.f_t;
    sliding[n + s] = load.sliding ? 1.0 : 0.0;
    wall[n + s] = is_wall(c.contacts.j[shown[s]]) ? 1.0 : 0.0;
  }

  std::string out;
  out.reserve(200 * points);
  out +=
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <UnstructuredGrid>\n";
  out += "    <Piece NumberOfPoints=\"" + std::to_string(points) + "\" NumberOfCells=\"" +
         std::to_string(cells) + "\">\n";
  out += "      <Points>\n";
  data_array(out, "Float64", "position", 3, xyz);
  out += "      </Points>\n      <PointData Scalars=\"radius\" Vectors=\"velocity\">\n";
  data_array(out, "Float64", "radius", 1, radius);
  data_array(out, "Float64", "velocity", 3, velocity);
  data_array(out, "Float64", "velocity_total", 3, velocity_total);
  data_array(out, "Float64", "spin", 1, spin);
  data_array(out, "Float64", "net_force", 3, force);
  out += "      </PointData>\n      <CellData Scalars=\"f_n\">\n";
  data_array(out, "Float64", "kind", 1, kind);
  data_array(out, "Float64", "f_n", 1, f_n);
  data_array(out, "Float64", "f_t", 1, f_t);
  data_array(out, "Float64", "sliding", 1, sliding);
  data_array(out, "Float64", "wall", 1, wall);
  out +=
      "      </CellData>\n      <Cells>\n"
      "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < n; ++i) put(out, i);
  for (std::size_t s = 0; s < shown.size(); ++s) {
    put(out, n + 2 * s);
    put(out, n + 2 * s + 1);
  }
  out +=
      "\n        </DataArray>\n"
      "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < n; ++i) put(out, i + 1);
  for (std::size_t s = 0; s < shown.size(); ++s) put(out, n + 2 * (s + 1));
  out +=
      "\n        </DataArray>\n"
      "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  // VTK_VERTEX = 1, VTK_LINE = 3.
  for (std::size_t i = 0; i < n; ++i) out += "1 ";
  for (std::size_t s = 0; s < shown.size(); ++s) out += "3 ";
  out +=
      "\n        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n"
      "</VTKFile>\n";
  return out;
}

void write_vtu(const Configuration& config, const std::filesystem::path& path) {
  write_file_atomically(path, format_vtu(config));
}

}  // namespace granstab

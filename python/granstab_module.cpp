// granstab._core (issue #22, docs/python.md): the data model with numpy views, and the commands
// run in this process with the GIL released. The package python/granstab/ builds the
// keyword-argument functions and result objects on top of run().
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "cli_app.hpp"
#include "common/configuration.hpp"
#include "common/io/configuration_file.hpp"
#include "common/material_override.hpp"
#include "common/measurements.hpp"
#include "common/progress.hpp"
#include "common/start_state.hpp"
#include "dynamic/protocols/run_guard.hpp"

namespace py = pybind11;
using granstab::Configuration;

namespace {

// A numpy view of one of the configuration's vectors: no copy; `owner` (the Python
// Configuration) is kept alive by the array. Valid while the vector is not resized.
template <class T>
py::array_t<T> view(std::vector<T>& v, py::handle owner) {
  return py::array_t<T>({static_cast<py::ssize_t>(v.size())}, {static_cast<py::ssize_t>(sizeof(T))},
                        v.data(), owner);
}

py::dict measurements_dict(const Configuration& c) {
  const granstab::Measurements m = granstab::measure(c);
  py::dict d;
  d["n_disks"] = m.n_disks;
  d["phi"] = m.phi;
  d["z"] = m.z;
  d["x0"] = m.x0;
  d["x_s"] = m.x_s;
  py::array_t<double> sigma({2, 2});
  auto s = sigma.mutable_unchecked<2>();
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) s(a, b) = m.sigma[a][b];
  d["sigma"] = sigma;
  d["q"] = m.q;
  d["epsilon_1"] = m.epsilon_1;
  d["epsilon_2"] = m.epsilon_2;
  d["epsilon_v"] = m.epsilon_v;
  d["e_c"] = m.e_c;
  d["f_2"] = m.f_2;
  d["n_contacts_carrying"] = m.n_contacts_carrying;
  d["n_sliding"] = m.n_sliding;
  d["n_rattlers"] = m.n_rattlers;
  return d;
}

// The run of one command line: GIL released; the progress observer takes the GIL at most every
// `interval` seconds to call `callback` and to let Python handle a pending Ctrl-C.
void run(const std::vector<std::string>& args, std::optional<py::function> callback,
         double interval) {
  using Clock = std::chrono::steady_clock;
  auto last =
      Clock::now() - std::chrono::duration_cast<Clock::duration>(
                         std::chrono::duration<double>(interval));  // the first update calls
  granstab::ProgressObserver observer = [&](std::string_view label, double done, double total,
                                            std::string_view detail) {
    const auto now = Clock::now();
    if (std::chrono::duration<double>(now - last).count() < interval) return;
    last = now;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // KeyboardInterrupt
    if (callback) (*callback)(std::string(label), done, total, std::string(detail));
  };
  std::string help;
  {
    py::gil_scoped_release release;
    granstab::ScopedProgressObserver scoped(observer);
    granstab::cli::run_command_line(args, &help);
  }
  if (!help.empty()) py::print(help);
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "granstab's compiled core; use the granstab package";
  static py::exception<std::runtime_error> error(m, "Error", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const granstab::protocols::Interrupted& e) {
      // SIGINT / SIGTERM during a dynamic run: its checkpoint is written (the message says how
      // to resume).
      PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
    } catch (const CLI::ParseError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const std::exception& e) {
      PyErr_SetString(error.ptr(), e.what());
    }
  });

  py::class_<Configuration>(m, "Configuration",
                            "A granstab configuration (docs/data-model.md). Array properties are "
                            "numpy views of the configuration's own storage (no copy).")
      .def(py::init<>())
      .def_static(
          "load", [](const std::string& path) { return granstab::read_configuration(path); },
          py::arg("path"))
      .def(
          "save",
          [](const Configuration& c, const std::string& path) {
            granstab::write_configuration(c, path);
          },
          py::arg("path"))
      .def("copy", [](const Configuration& c) { return Configuration(c); })
      .def_property_readonly("n_disks", [](const Configuration& c) { return c.disks.size(); })
      .def_property_readonly(
          "x", [](py::object self) { return view(self.cast<Configuration&>().disks.x, self); })
      .def_property_readonly(
          "y", [](py::object self) { return view(self.cast<Configuration&>().disks.y, self); })
      .def_property_readonly(
          "radius",
          [](py::object self) { return view(self.cast<Configuration&>().disks.radius, self); })
      .def_property_readonly(
          "mass",
          [](py::object self) { return view(self.cast<Configuration&>().disks.mass, self); })
      .def_property_readonly(
          "inertia",
          [](py::object self) { return view(self.cast<Configuration&>().disks.inertia, self); })
      .def_property_readonly(
          "vx", [](py::object self) { return view(self.cast<Configuration&>().disks.vx, self); })
      .def_property_readonly(
          "vy", [](py::object self) { return view(self.cast<Configuration&>().disks.vy, self); })
      .def_property_readonly(
          "omega",
          [](py::object self) { return view(self.cast<Configuration&>().disks.omega, self); })
      .def_property_readonly(
          "theta",
          [](py::object self) { return view(self.cast<Configuration&>().disks.theta, self); })
      .def_property_readonly("n_contacts", [](const Configuration& c) { return c.contacts.size(); })
      .def_property_readonly(
          "contact_i",
          [](py::object self) { return view(self.cast<Configuration&>().contacts.i, self); })
      .def_property_readonly(
          "contact_j",
          [](py::object self) { return view(self.cast<Configuration&>().contacts.j, self); })
      .def_property_readonly(
          "contact_k1",
          [](py::object self) { return view(self.cast<Configuration&>().contacts.k1, self); })
      .def_property_readonly(
          "contact_k2",
          [](py::object self) { return view(self.cast<Configuration&>().contacts.k2, self); })
      .def_property_readonly(
          "delta_t",
          [](py::object self) { return view(self.cast<Configuration&>().contacts.delta_t, self); })
      .def_property_readonly(
          "contact_status",
          [](const Configuration& c) {
            // A copy: the statuses are an enum (0 stick, 1 slide +, 2 slide -, 3 open).
            py::array_t<std::uint8_t> a(static_cast<py::ssize_t>(c.contacts.size()));
            auto v = a.mutable_unchecked<1>();
            for (std::size_t k = 0; k < c.contacts.size(); ++k)
              v(static_cast<py::ssize_t>(k)) = static_cast<std::uint8_t>(c.contacts.status[k]);
            return a;
          })
      .def_property_readonly(
          "boundary",
          [](const Configuration& c) { return c.cell.periodic() ? "periodic" : "walls"; })
      .def_property(
          "length",
          [](const Configuration& c) {
            return py::array_t<double>(2, c.cell.length.data());  // a copy of (L1, L2)
          },
          [](Configuration& c, std::array<double, 2> l) { c.cell.length = l; })
      .def_property(
          "k_n", [](const Configuration& c) { return c.material.k_n; },
          [](Configuration& c, double v) { c.material.k_n = v; })
      .def_property(
          "k_t", [](const Configuration& c) { return c.material.k_t; },
          [](Configuration& c, double v) { c.material.k_t = v; })
      .def_property(
          "mu", [](const Configuration& c) { return c.material.mu; },
          [](Configuration& c, double v) { c.material.mu = v; })
      .def_property(
          "zeta", [](const Configuration& c) { return c.material.zeta; },
          [](Configuration& c, double v) { c.material.zeta = v; })
      .def_property(
          "mu_wall", [](const Configuration& c) { return c.material.mu_wall; },
          [](Configuration& c, double v) { c.material.mu_wall = v; })
      .def_property_readonly(
          "kappa",
          [](const Configuration& c) {
            return c.material.kappa(c.stage.sigma_ext[0] > 0.0 ? c.stage.sigma_ext[0] : 1.0);
          })
      .def_property_readonly("kt_ratio",
                             [](const Configuration& c) { return c.material.kt_over_kn(); })
      .def_property_readonly(
          "sigma_ext",
          [](const Configuration& c) { return py::array_t<double>(2, c.stage.sigma_ext.data()); })
      .def("measure", &measurements_dict,
           "SPEC §2 measurements (Phi, z, x0, X_s, stress, q, strains, e_c, f_2) as a dict")
      .def_property_readonly("phi", [](const Configuration& c) { return granstab::measure(c).phi; })
      .def_property_readonly("z", [](const Configuration& c) { return granstab::measure(c).z; })
      .def_property_readonly("x0", [](const Configuration& c) { return granstab::measure(c).x0; })
      .def_property_readonly("x_s", [](const Configuration& c) { return granstab::measure(c).x_s; })
      .def_property_readonly("q", [](const Configuration& c) { return granstab::measure(c).q; })
      .def_property_readonly("e_c", [](const Configuration& c) { return granstab::measure(c).e_c; })
      .def_property_readonly("f_2", [](const Configuration& c) { return granstab::measure(c).f_2; })
      .def(
          "apply_material",
          [](Configuration& c, std::optional<double> mu, std::optional<double> kt_ratio,
             bool clip_to_cone) {
            granstab::MaterialOverrides o;
            o.mu = mu;
            o.kt_ratio = kt_ratio;
            o.clip_to_cone = clip_to_cone;
            return granstab::apply_material_overrides(c, o).clipped;
          },
          py::arg("mu") = py::none(), py::arg("kt_ratio") = py::none(),
          py::arg("clip_to_cone") = false,
          "The biaxial material as q1 --mu/--kt-ratio set it (K_T changes keep the tangential "
          "forces); returns the number of contacts clipped onto the cone")
      .def(
          "check_start",
          [](const Configuration& c) {
            const granstab::StartStateReport r = granstab::check_start_state(c);
            py::dict d;
            d["geometry"] = r.geometry;
            d["in_equilibrium"] = r.equilibrium.in_equilibrium;
            d["equilibrium"] = granstab::equilibrium_failures(r.equilibrium);
            return d;
          },
          "What q1, compare and probe check before they start (common/start_state.hpp)");

  m.def("run", &run, py::arg("args"), py::arg("progress") = py::none(), py::arg("interval") = 0.1,
        "Runs `granstab ARGS...` in this process with the GIL released; progress(label, done, "
        "total, detail) is called at most every `interval` seconds");
}

#include "configuration_file.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "common/atomic_file.hpp"

namespace granstab {
namespace {

constexpr std::string_view magic = "granstab-configuration";

// Messages are built by appending: GCC 12 reports false -Wrestrict warnings on chains of
// "literal" + std::string temporaries.
template <class... Parts>
std::string cat(const Parts&... parts) {
  std::string s;
  (s.append(std::string_view(parts)), ...);
  return s;
}

std::string shortest(double v) {
  std::array<char, 64> buf;
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), r.ptr);
}

template <class T>
struct Named {
  std::string_view name;
  T value;
};

constexpr std::array<Named<Boundary>, 2> boundary_names{
    {{"periodic", Boundary::periodic}, {"walls", Boundary::walls}}};
constexpr std::array<Named<LengthControl>, 3> control_names{
    {{"stress", LengthControl::stress},
     {"strain_rate", LengthControl::strain_rate},
     {"fixed", LengthControl::fixed}}};
constexpr std::array<Named<StressMeasure>, 2> measure_names{
    {{"cauchy", StressMeasure::cauchy}, {"nominal", StressMeasure::nominal}}};
constexpr std::array<Named<ContactStatus>, 4> status_names{
    {{"stick", ContactStatus::stick},
     {"slide+", ContactStatus::slide_positive},
     {"slide-", ContactStatus::slide_negative},
     {"open", ContactStatus::open}}};
constexpr std::array<Named<Wall>, 4> wall_names{
    {{"left", wall_left}, {"right", wall_right}, {"bottom", wall_bottom}, {"top", wall_top}}};

template <class T, std::size_t n>
std::string_view name_of(const std::array<Named<T>, n>& names, T value) {
  for (const auto& e : names)
    if (e.value == value) return e.name;
  throw std::invalid_argument("write_configuration: invalid enumeration value");
}

template <class T, std::size_t n>
std::string choices(const std::array<Named<T>, n>& names) {
  std::string s;
  for (const auto& e : names) s += (s.empty() ? "" : ", ") + std::string(e.name);
  return s;
}

// A std::mt19937_64 state as written by operator<<, and nothing else.
bool is_rng_state(const std::string& state) {
  std::istringstream in(state);
  std::mt19937_64 generator;
  in >> generator;
  if (in.fail()) return false;
  in >> std::ws;
  return in.eof();
}

// ------------------------------------------------------------------------------------- writing

class Writer {
 public:
  std::string text;

  Writer& word(std::string_view w) {
    if (!text.empty() && text.back() != '\n') text += ' ';
    text += w;
    return *this;
  }
  // Shortest representation that reads back to the same double (std::to_chars guarantees it).
  Writer& number(double v, std::string_view field) {
    if (!std::isfinite(v))
      throw std::invalid_argument("write_configuration: " + std::string(field) + " is not finite");
    std::array<char, 64> buf;
    const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    return word(std::string_view(buf.data(), static_cast<std::size_t>(r.ptr - buf.data())));
  }
  template <class Int>
  Writer& integer(Int v) {
    std::array<char, 32> buf;
    const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    return word(std::string_view(buf.data(), static_cast<std::size_t>(r.ptr - buf.data())));
  }
  Writer& pair(std::string_view key, const std::array<double, 2>& v) {
    return word(key).number(v[0], key).number(v[1], key).end_line();
  }
  Writer& scalar(std::string_view key, double v) { return word(key).number(v, key).end_line(); }
  Writer& comment(std::string_view c) {
    text += "# ";
    text += c;
    return end_line();
  }
  Writer& end_line() {
    text += '\n';
    return *this;
  }
};

// ------------------------------------------------------------------------------------- reading

class Reader {
 public:
  Reader(std::string_view text, const std::string& source) : text_(text), source_(source) {}

  // Moves to the next line holding data: '#' starts a comment, blank lines are skipped.
  bool advance() {
    while (pos_ < text_.size()) {
      std::size_t end = text_.find('\n', pos_);
      if (end == std::string_view::npos) end = text_.size();
      std::string_view line = text_.substr(pos_, end - pos_);
      pos_ = end + 1;
      ++line_;
      if (const auto hash = line.find('#'); hash != std::string_view::npos)
        line = line.substr(0, hash);
      tokens_.clear();
      std::size_t i = 0;
      while (i < line.size()) {
        while (i < line.size() && is_space(line[i])) ++i;
        std::size_t j = i;
        while (j < line.size() && !is_space(line[j])) ++j;
        if (j > i) tokens_.push_back(line.substr(i, j - i));
        i = j;
      }
      if (!tokens_.empty()) return true;
    }
    return false;
  }

  // An empty file has no line 0: report line 1.
  [[noreturn]] void fail(const std::string& message) const { fail_at(std::max(line_, 1), message); }
  [[noreturn]] void fail_at(int line, const std::string& message) const {
    throw std::runtime_error(source_ + ":" + std::to_string(line) + ": " + message);
  }
  void require_more(const std::string& expected) {
    if (!advance()) fail("unexpected end of file, expected " + expected + " (truncated file?)");
  }

  int line() const { return line_; }
  std::size_t size() const { return tokens_.size(); }
  std::string_view token(std::size_t k) const { return tokens_[k]; }

  // The next data line must be `keyword` followed by exactly n_values values.
  void keyword_line(std::string_view keyword, std::size_t n_values) {
    require_more(cat("'", keyword, "'"));
    const std::string_view found = tokens_[0];
    if (found != keyword) {
      if (looks_numeric(found))
        fail(cat("expected '", keyword,
                 "', found a data line (more lines than the declared count?)"));
      if (is_known_keyword(found)) fail(cat("expected '", keyword, "', found '", found, "'"));
      fail(cat("unknown keyword '", found, "' (expected '", keyword, "')"));
    }
    values(n_values, keyword);
  }
  // The current line must carry exactly n values after its first token (or n tokens in all
  // when what names a data line).
  void values(std::size_t n, std::string_view what, std::size_t first = 1) {
    const std::size_t have = tokens_.size() - first;
    if (have < n)
      fail(std::string(what) + ": expected " + std::to_string(n) + " values, found " +
           std::to_string(have));
    if (have > n)
      fail(cat(what, ": trailing garbage '", tokens_[first + n], "' after ", std::to_string(n),
               " values"));
  }

  double real(std::size_t k, const std::string& what) const {
    const std::string_view t = tokens_[k];
    double v = 0.0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (r.ec == std::errc::result_out_of_range)
      fail(what + " = " + std::string(t) + ": out of the range of a double");
    if (r.ec != std::errc() || r.ptr != t.data() + t.size())
      fail(cat(what, ": '", t, "' is not a number"));
    if (!std::isfinite(v)) fail(what + " = " + std::string(t) + ": must be finite");
    return v;
  }
  template <class Int>
  Int integer(std::size_t k, const std::string& what) const {
    const std::string_view t = tokens_[k];
    Int v{};
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (r.ec == std::errc::result_out_of_range)
      fail(what + " = " + std::string(t) + ": integer out of range");
    if (r.ec != std::errc() || r.ptr != t.data() + t.size())
      fail(cat(what, ": '", t, "' is not an integer"));
    return v;
  }
  template <class T, std::size_t n>
  T name(std::size_t k, const std::array<Named<T>, n>& names, const std::string& what) const {
    for (const auto& e : names)
      if (e.name == tokens_[k]) return e.value;
    fail(cat(what, ": unknown value '", tokens_[k], "' (one of ", choices(names), ")"));
  }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r'; }
  static bool looks_numeric(std::string_view t) {
    const char c = t.front();
    return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.';
  }
  static bool is_known_keyword(std::string_view t) {
    static constexpr std::array<std::string_view, 21> known{"time",
                                                            "step",
                                                            "rng_state",
                                                            "boundary",
                                                            "cell.length",
                                                            "cell.length_rate",
                                                            "cell.mass",
                                                            "material.k_n",
                                                            "material.k_t",
                                                            "material.mu",
                                                            "material.zeta",
                                                            "material.mu_wall",
                                                            "stage.reference_length",
                                                            "stage.sigma_ext",
                                                            "stage.control",
                                                            "stage.strain_rate",
                                                            "stage.measure",
                                                            "disks",
                                                            "contacts",
                                                            "end",
                                                            magic};
    for (const auto k : known)
      if (k == t) return true;
    return false;
  }

  std::string_view text_;
  const std::string& source_;
  std::size_t pos_ = 0;
  int line_ = 0;
  std::vector<std::string_view> tokens_;
};

std::array<double, 2> read_pair(Reader& in, std::string_view key) {
  in.keyword_line(key, 2);
  const std::string k(key);
  return {in.real(1, k + "[1]"), in.real(2, k + "[2]")};
}

double read_scalar(Reader& in, std::string_view key) {
  in.keyword_line(key, 1);
  return in.real(1, std::string(key));
}

void read_header(Reader& in) {
  if (!in.advance()) in.fail("empty file, expected 'granstab-configuration 1'");
  if (in.token(0) != magic)
    in.fail(cat("not a granstab configuration (the first line must be '", magic, " ",
                std::to_string(configuration_format_version), "')"));
  in.values(1, magic);
  const std::string_view version = in.token(1);
  if (version != std::to_string(configuration_format_version))
    in.fail(cat("unknown format version '", version, "' (this granstab reads version ",
                std::to_string(configuration_format_version), ")"));
}

void read_run_state(Reader& in, Configuration& c) {
  c.time = read_scalar(in, "time");
  in.keyword_line("step", 1);
  c.step = in.integer<std::uint64_t>(1, "step");
  in.require_more("'rng_state'");
  if (in.token(0) != "rng_state") in.fail(cat("expected 'rng_state', found '", in.token(0), "'"));
  std::string state;
  for (std::size_t k = 1; k < in.size(); ++k) {
    if (k > 1) state += ' ';
    state += in.token(k);
  }
  if (!state.empty() && !is_rng_state(state))
    in.fail("rng_state: not a std::mt19937_64 state (313 unsigned integers)");
  c.rng_state = std::move(state);
}

void read_cell(Reader& in, Cell& cell) {
  in.keyword_line("boundary", 1);
  cell.boundary = in.name(1, boundary_names, "boundary");
  cell.length = read_pair(in, "cell.length");
  const int length_line = in.line();
  cell.length_rate = read_pair(in, "cell.length_rate");
  const int rate_line = in.line();
  cell.mass = read_pair(in, "cell.mass");
  try {
    validate(cell);
  } catch (const std::invalid_argument& e) {
    // validate() names the field (cell.L1, cell.L1_rate or cell.mass1); point at its line.
    const std::string what = e.what();
    const int line = what.starts_with("cell.mass")             ? in.line()
                     : what.find("_rate") != std::string::npos ? rate_line
                                                               : length_line;
    in.fail_at(line, what);
  }
}

void read_material(Reader& in, Material& m) {
  // The keys are the field names validate() uses, so its message finds its line.
  const std::array<std::pair<std::string_view, double*>, 5> fields{
      {{"material.k_n", &m.k_n},
       {"material.k_t", &m.k_t},
       {"material.mu", &m.mu},
       {"material.zeta", &m.zeta},
       {"material.mu_wall", &m.mu_wall}}};
  std::array<int, 5> lines{};
  for (std::size_t f = 0; f < fields.size(); ++f) {
    *fields[f].second = read_scalar(in, fields[f].first);
    lines[f] = in.line();
  }
  try {
    validate(m);
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    int line = in.line();
    for (std::size_t f = 0; f < fields.size(); ++f)
      if (what.starts_with(std::string(fields[f].first) + ":")) line = lines[f];
    in.fail_at(line, what);
  }
}

void read_stage(Reader& in, Stage& s) {
  s.reference_length = read_pair(in, "stage.reference_length");
  for (int a = 0; a < 2; ++a)
    if (!(s.reference_length[a] > 0.0))
      in.fail("stage.reference_length[" + std::to_string(a + 1) + "] must be > 0");
  s.sigma_ext = read_pair(in, "stage.sigma_ext");
  in.keyword_line("stage.control", 2);
  s.control = {in.name(1, control_names, "stage.control[1]"),
               in.name(2, control_names, "stage.control[2]")};
  s.strain_rate = read_pair(in, "stage.strain_rate");
  in.keyword_line("stage.measure", 1);
  s.measure = in.name(1, measure_names, "stage.measure");
}

std::size_t read_count(Reader& in, std::string_view keyword) {
  in.keyword_line(keyword, 1);
  const auto n = in.integer<std::int64_t>(1, std::string(keyword));
  if (n < 0) in.fail(std::string(keyword) + " = " + std::to_string(n) + ": must be >= 0");
  if (n > std::numeric_limits<std::int32_t>::max())
    in.fail(std::string(keyword) + " = " + std::to_string(n) + ": too many (indices are 32-bit)");
  return static_cast<std::size_t>(n);
}

void read_disks(Reader& in, Configuration& c) {
  const std::size_t n = read_count(in, "disks");
  Disks& d = c.disks;
  // Grown line by line: a corrupt count must not allocate before the lines are there.
  d.reserve(std::min<std::size_t>(n, 1u << 16));
  const auto fields = d.fields();  // x y radius mass inertia vx vy omega theta: the file's columns
  static constexpr std::array<std::string_view, 9> columns{"x",  "y",  "radius", "mass", "inertia",
                                                           "vx", "vy", "omega",  "theta"};
  const Cell& cell = c.cell;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string disk = "disk " + std::to_string(i);
    in.require_more(disk + " (the file declares " + std::to_string(n) + " disks)");
    if (in.token(0) == "contacts")
      in.fail("found 'contacts' after " + std::to_string(i) +
              " disk lines, but the file declares " + std::to_string(n) + " disks");
    in.values(9, disk, 0);
    for (std::size_t f = 0; f < columns.size(); ++f)
      fields[f]->push_back(in.real(f, cat(disk, " ", columns[f])));
    if (!(d.radius[i] > 0.0)) in.fail(disk + ": radius must be > 0");
    if (!(d.mass[i] > 0.0)) in.fail(disk + ": mass must be > 0");
    if (!(d.inertia[i] > 0.0)) in.fail(disk + ": inertia must be > 0");
    const std::array<double, 2> r{d.x[i], d.y[i]};
    for (int a = 0; a < 2; ++a) {
      const double L = cell.length[a];
      // Periodic positions are wrapped into [0, L); a wall-bounded centre lies in the box.
      const bool inside = cell.periodic() ? (r[a] >= 0.0 && r[a] < L) : (r[a] >= 0.0 && r[a] <= L);
      if (!inside)
        in.fail(cat(disk, a == 0 ? ": x = " : ": y = ", shortest(r[a]), " is outside ",
                    cell.periodic() ? "the periodic cell [0, " : "the walls [0, ", shortest(L),
                    cell.periodic() ? ")" : "]"));
    }
  }
}

void read_contacts(Reader& in, Configuration& c) {
  const std::size_t n = read_count(in, "contacts");
  const auto n_disks = static_cast<std::int64_t>(c.disks.size());
  const bool periodic = c.cell.periodic();
  Contacts& k = c.contacts;
  k.clear();
  k.reserve(std::min<std::size_t>(n, 1u << 16));
  for (std::size_t m = 0; m < n; ++m) {
    const std::string contact = "contact " + std::to_string(m);
    in.require_more(contact + " (the file declares " + std::to_string(n) + " contacts)");
    if (in.token(0) == "end")
      in.fail("found 'end' after " + std::to_string(m) + " contact lines, but the file declares " +
              std::to_string(n) + " contacts");
    in.values(6, contact, 0);
    const auto i = in.integer<std::int64_t>(0, contact + " i");
    if (i < 0 || i >= n_disks)
      in.fail(contact + ": i = " + std::to_string(i) + " out of range [0, " +
              std::to_string(n_disks) + ")");
    std::int64_t j = 0;
    bool wall = false;
    for (const auto& w : wall_names)
      if (in.token(1) == w.name) {
        j = w.value;
        wall = true;
      }
    if (wall && periodic)
      in.fail(cat(contact, ": wall contact '", in.token(1), "' in a periodic cell"));
    if (!wall) {
      j = in.integer<std::int64_t>(1, contact + " j");
      if (j < 0 || j >= n_disks)
        in.fail(contact + ": j = " + std::to_string(j) + " out of range [0, " +
                std::to_string(n_disks) + ") (walls are named left, right, bottom, top)");
    }
    const auto k1 = in.integer<std::int32_t>(2, contact + " k1");
    const auto k2 = in.integer<std::int32_t>(3, contact + " k2");
    if (!periodic && (k1 != 0 || k2 != 0))
      in.fail(contact + ": image shift (" + std::to_string(k1) + ", " + std::to_string(k2) +
              ") must be (0, 0) between walls");
    if (i == j && k1 == 0 && k2 == 0)
      in.fail(contact + ": disk " + std::to_string(i) + " in contact with itself");
    const double delta_t = in.real(4, contact + " delta_t");
    const ContactStatus status = in.name(5, status_names, contact + " status");
    k.add(static_cast<int>(i), static_cast<int>(j), k1, k2, delta_t, status);
  }
}

}  // namespace

std::string format_configuration(const Configuration& c) {
  if (!c.rng_state.empty() && !is_rng_state(c.rng_state))
    throw std::invalid_argument("write_configuration: rng_state is not a std::mt19937_64 state");
  Writer w;
  w.word(magic).integer(configuration_format_version).end_line();
  w.comment("granstab configuration, see docs/file-format.md. Units a = 1, m = 1, P = 1;");
  w.comment("compression positive. Numbers are the shortest decimals that read back bit-exactly.");
  w.scalar("time", c.time);
  w.word("step").integer(c.step).end_line();
  w.word("rng_state");
  if (!c.rng_state.empty()) w.word(c.rng_state);
  w.end_line();
  w.comment("cell: [0, L1] x [0, L2]; walls: x = L1 and y = L2 are the mobile walls");
  w.word("boundary").word(name_of(boundary_names, c.cell.boundary)).end_line();
  w.pair("cell.length", c.cell.length);
  w.pair("cell.length_rate", c.cell.length_rate);
  w.pair("cell.mass", c.cell.mass);
  w.scalar("material.k_n", c.material.k_n);
  w.scalar("material.k_t", c.material.k_t);
  w.scalar("material.mu", c.material.mu);
  w.scalar("material.zeta", c.material.zeta);
  w.scalar("material.mu_wall", c.material.mu_wall);
  w.pair("stage.reference_length", c.stage.reference_length);
  w.pair("stage.sigma_ext", c.stage.sigma_ext);
  w.word("stage.control")
      .word(name_of(control_names, c.stage.control[0]))
      .word(name_of(control_names, c.stage.control[1]))
      .end_line();
  w.pair("stage.strain_rate", c.stage.strain_rate);
  w.word("stage.measure").word(name_of(measure_names, c.stage.measure)).end_line();

  const Disks& d = c.disks;
  w.word("disks").integer(d.size()).end_line();
  w.comment("x y radius mass inertia vx vy omega theta   (v: fluctuating velocity)");
  for (std::size_t i = 0; i < d.size(); ++i) {
    w.number(d.x[i], "disk x").number(d.y[i], "disk y").number(d.radius[i], "disk radius");
    w.number(d.mass[i], "disk mass").number(d.inertia[i], "disk inertia");
    w.number(d.vx[i], "disk vx").number(d.vy[i], "disk vy").number(d.omega[i], "disk omega");
    w.number(d.theta[i], "disk theta").end_line();
  }
  const Contacts& k = c.contacts;
  w.word("contacts").integer(k.size()).end_line();
  w.comment("i j k1 k2 delta_t status   (l = r_j + (k1 L1, k2 L2) - r_i; j may name a wall)");
  for (std::size_t m = 0; m < k.size(); ++m) {
    w.integer(k.i[m]);
    if (is_wall(k.j[m]))
      w.word(name_of(wall_names, static_cast<Wall>(k.j[m])));
    else
      w.integer(k.j[m]);
    w.integer(k.k1[m]).integer(k.k2[m]).number(k.delta_t[m], "contact delta_t");
    w.word(name_of(status_names, k.status[m])).end_line();
  }
  w.word("end").end_line();
  return std::move(w.text);
}

Configuration parse_configuration(std::string_view text, const std::string& source_name) {
  Reader in(text, source_name);
  Configuration c;
  read_header(in);
  read_run_state(in, c);
  read_cell(in, c.cell);
  read_material(in, c.material);
  read_stage(in, c.stage);
  read_disks(in, c);
  read_contacts(in, c);
  in.keyword_line("end", 0);
  if (in.advance()) in.fail(cat("trailing content after 'end': '", in.token(0), "'"));
  return c;
}

Configuration read_configuration(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw std::runtime_error(path.string() + ": cannot open configuration file");
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) throw std::runtime_error(path.string() + ": read error");
  return parse_configuration(text.str(), path.string());
}

void write_configuration(const Configuration& config, const std::filesystem::path& path) {
  const std::string text = format_configuration(config);
  // One set of rules: the writer refuses exactly what the reader would reject (a disk outside
  // the cell, a contact index out of range, ...), so every file written can be read back.
  try {
    parse_configuration(text, path.string());
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(
        cat("write_configuration: invalid configuration, not written: ", e.what()));
  }
  write_file_atomically(path, text);
}

}  // namespace granstab

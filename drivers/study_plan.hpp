#pragma once
// A study (issue #20, docs/studies.md): a grid of parameter values, each point a pipeline of
// granstab commands. The plan is what the study file says, expanded into tasks: one task per
// step and per distinct value of the grid keys the step depends on (`vary`), so that, e.g., one
// prepared sample serves the q1 runs at several K_T/K_N. Pure: reading and expanding only; the
// runner (study_runner.hpp) executes the tasks.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace granstab::study {

struct GridKey {
  std::string name;
  std::vector<std::string> values;  // as written in the study file (TOML numbers: shortest form)
};

struct Step {
  std::string name;                    // unique; {name} in later steps is this step's directory
  std::string command;                 // prepare, biaxial, creep, perturb, q1, compare, probe
  std::vector<std::string> vary;       // grid keys this step depends on, in grid order
  std::filesystem::path settings;      // the settings file (prepare, biaxial, ...), absolute
  std::vector<std::string> set;        // "key=value" templates, passed as --set
  std::vector<std::string> arguments;  // argument templates
};

struct Task {
  std::size_t step = 0;              // index into Plan::steps
  std::vector<std::size_t> value;    // index into grid[k].values for each key of the step's vary
  std::filesystem::path directory;   // absolute
  std::vector<std::string> argv;     // the granstab arguments (no program name), expanded
  std::vector<std::size_t> depends;  // tasks that must be done first (earlier steps of its points)
  std::size_t root = 0;              // the task of the first step its points share (MPI dealing)
};

struct Point {
  std::vector<std::size_t> value;  // index into grid[k].values for every key
  std::vector<std::size_t> tasks;  // one per step
};

struct Plan {
  std::filesystem::path file;  // the study file
  std::filesystem::path out;   // output directory, absolute
  std::vector<GridKey> grid;
  std::vector<Step> steps;
  std::vector<Task> tasks;  // in an order where every dependency comes first
  std::vector<Point> points;
};

// Reads and expands a study file. Every error names the file, the line and the key:
// std::invalid_argument "FILE:LINE: KEY: what is wrong".
Plan read_plan(const std::filesystem::path& file);

// study.json: the grid, the points with their values and each step's directory and command line,
// for the report (scripts/study/study_report.py) and for a reader of the output directory.
std::string plan_json(const Plan& plan);

}  // namespace granstab::study

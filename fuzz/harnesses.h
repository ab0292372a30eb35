#pragma once
// The fuzz harnesses, one per reader of user files plus one that runs the pipeline. Each takes the bytes
// of a would-be file and checks kincal's promise about bad input (docs/RELIABILITY.md): a reader either
// accepts the file or throws std::invalid_argument with one line that begins with the file's name. Any
// other exception, a message that does not say where, a NaN in an output, or a sanitizer report is a
// finding: the harness aborts. The same functions run under libFuzzer (fuzz build, clang) and under the
// replay driver that ctest runs on every file in fuzz/regressions/ (ordinary build).
#include <cstddef>
#include <cstdint>

namespace kincal::fuzz {

int FuzzRobotFile(const uint8_t* data, size_t size);  // robot YAML; accepted robots round-trip
int FuzzDataset(const uint8_t* data, size_t size);    // dataset CSV; accepted datasets round-trip
int FuzzTargets(const uint8_t* data, size_t size);    // targets CSV for a 6-joint robot
int FuzzStudyFile(const uint8_t* data, size_t size);  // study YAML (parsed and planned, not run)
// First byte picks a registered estimator or compensator; the rest is its options (YAML).
int FuzzOptions(const uint8_t* data, size_t size);
// A robot file, a line "@@", then a dataset: a short identify (least_squares) and compensate (jacobian)
// of the first rows when both readers accept them.
int FuzzPipeline(const uint8_t* data, size_t size);
// A URDF, optionally after a line "@@ BASE TIP [CONVENTION]": imported between those links (or else
// between the root and each link); an accepted robot is written as a robot file and as URDF (the
// source edited, and a new file), and each must read back with the same kinematics.
int FuzzUrdf(const uint8_t* data, size_t size);
// First byte picks a registered program format (alphabetical, modulo their count), the rest is a program:
// accepted targets lie in the text, and written back unchanged by the format's writer they read the same.
int FuzzPrograms(const uint8_t* data, size_t size);

}  // namespace kincal::fuzz

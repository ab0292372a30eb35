# kincal's public API: the headers installed under include/kincal/, with the paths they have in the tree
# (#include "estimators/estimator.h" works the same inside kincal and against an installed kincal). Every
# other header is internal: it is not installed and may change without notice. scripts/check_layers fails
# when a header of this list includes one that is not in it, so the list stays closed under #include.
# What a plugin or a program built on kincal uses (docs/extending.md, "The public API"):
set(KINCAL_PUBLIC_HEADERS
  # The core: errors, units, options tables, registries by name and the plugin registrar.
  framework/dataset.h
  framework/error.h
  framework/extension_points.h
  framework/kinematic_model.h
  framework/math.h
  framework/named_registry.h
  framework/options.h
  framework/plugin.h
  framework/random.h
  framework/registry.h
  framework/units.h
  framework/version.h
  # Kinematic models: the conventions' registry, the chain of elementary operations a convention builds
  # on, the conversions between conventions, joint and drive errors.
  models/chain_model.h
  models/conversion.h
  models/drive_model.h
  models/joint_errors.h
  models/model_factory.h
  # The robot: its file, fixtures, joint readings, predictions and simulated datasets.
  robot/fixtures.h
  robot/joint_readings.h
  robot/prediction.h
  robot/robot.h
  robot/robot_file.h
  robot/simulator.h
  robot/simulator_instruments.h
  # The two method interfaces and their writable registries.
  estimators/builtin.h
  estimators/estimator.h
  compensators/builtin.h
  compensators/compensation_targets.h
  compensators/compensator.h
  # Robot program formats.
  programs/program.h
  # The conformance kits for plugin authors (header-only, on GoogleTest).
  testing/compensator_conformance.h
  testing/estimator_conformance.h
  testing/model_conformance.h
)

# mechgen_add_model(<name> <model.yaml> [NO_SWEEP] [STATICS|NO_STATICS]
#                   [SIMULATE|NO_SIMULATE] [ENGINE] [FLYWHEEL] [STRATEGY blocks|monolithic])
#
# Runs `mechgen generate` on <model.yaml> at build time (again whenever the model, the
# templates or the mechgen program change) and defines:
#   mechgen_model_<name>   a static library (alias mechgen::model_<name>) whose include
#                          directory holds <name>.h; link a product against it. It needs
#                          Eigen only (and mechgen/core/model_view.h for its model view,
#                          mech::<name>::View(), compiled from <name>_view.cc).
# and the model's command-line tools (runtime/tools/*_main.cc compiled against <name>.h):
#   <name>_sweep           the sweep command (positions, K, L, points over the inputs' range;
#                          table, CSV, SVG). Needs mechgen::runtime_ceres (Ceres).
#   <name>_statics         the statics command (runtime/tools/statics_main.cc: driving forces,
#                          reactions, dead zones, equilibria; CSV, SVG), for a model with
#                          `forces`. Needs mechgen::runtime_ceres.
#   <name>_simulate        the forward-dynamics command (runtime/tools/simulate_main.cc: a
#                          transient to a steady state; CSV for plot_dynamics.gnuplot), for a
#                          model with `dynamics`. Eigen only.
#   <name>_engine          with ENGINE only: the engine command (runtime/tools/engine_main.cc:
#                          crank torque over a cycle, bearing loads, flywheel, run-up) of a model
#                          made by tools/make_engine.py (it reads the engine's parameters by
#                          name, which no quantity says). Eigen only.
#   <name>_flywheel        with FLYWHEEL only: the flywheel command (runtime/tools/
#                          flywheel_main.cc: the driving torque at constant speed over a cycle,
#                          its energy loop, the flywheel for a C_s, with `dynamics` a simulated
#                          check), for a one-input model with `forces` (a stub without). Eigen
#                          only. Opt-in, so that the shipped models' build does not grow; any
#                          model file has it as `mechgen flywheel MODEL`.
#
# What a model has is what the generator says, never a reading of the YAML here, and which
# tool needs which quantity is the generator's table too (generator/driver/tool_command.cc,
# the one `mechgen <tool> MODEL` checks): its quantities as the generator's model reader
# resolves them, with what they imply (`dynamics` brings K, L, forces and potential;
# `shaking` brings dynamics), and the tools they allow, as
# `mechgen generate <model.yaml> --print-tools` prints them. Two cases:
#  - mechgen is installed (find_package(mechgen)): it is asked at configure time (again when
#    the model file changes), and only the tools the model has are defined;
#  - mechgen is built by this project (its target `mechgen` exists): it cannot run at
#    configure time, so every tool is defined, and the generation also writes a manifest
#    (<name>_manifest.h: MECHGEN_MODEL_TOOL_STATICS 0|1 and the quantity it needs, ...;
#    `mechgen generate --manifest`) from which each tool compiles as the tool itself or, for a
#    model without what it needs, as a stub (a few lines, no runtime) that says so and exits
#    with status 2.
# Either way a tool that runs is the real tool exactly when the model's quantities allow it.
#
# Options:
#   NO_SWEEP               no tools at all: the library only (nothing here needs Ceres).
#   STATICS | NO_STATICS   define <name>_statics even where the model is known to lack
#                          `forces` (its stub) | never define it.
#   SIMULATE | NO_SIMULATE the same for <name>_simulate and `dynamics`.
#   ENGINE                 define <name>_engine (a stub without `dynamics`).
#   FLYWHEEL               define <name>_flywheel (a stub without `forces`).
#   STRATEGY blocks|monolithic   passed to `mechgen generate --strategy` (default blocks).
# The cache variable MECHGEN_BUILD_SWEEPS (default ON) OFF defines no tools for any model (as
# NO_SWEEP everywhere); without Ceres (no target mechgen::runtime_ceres) there are no
# <name>_sweep and <name>_statics, the Eigen-only tools remain.
#
# Every tool defined is appended to the global property MECHGEN_MODEL_TOOLS (mechgen's own
# build leaves the untested ones out of `all` in its test command: top-level CMakeLists.txt).
#
# The variable MECHGEN_TOOL_COMPILE_OPTIONS (default empty: the project's flags) is added to
# every tool's compile options; mechgen's own build sets it to -O2 for Release (see the
# top-level CMakeLists.txt for what that saves).
#
# Requires MECHGEN_EXECUTABLE, MECHGEN_TEMPLATES_DIR and MECHGEN_TOOLS_DIR (set by the build
# tree or by find_package(mechgen)).
include_guard(GLOBAL)

# OFF skips every <model>_sweep tool (e.g. the sanitizer build: one executable per model
# that no test runs).
option(MECHGEN_BUILD_SWEEPS "Build the <model>_sweep tool of each mechgen_add_model()" ON)

# The source every tool but the sweep compiles: the tool's main where the model's manifest
# says it has what the tool needs, else a stub.
set(_MECHGEN_TOOL_SOURCE "${CMAKE_BINARY_DIR}/CMakeFiles/mechgen/tool_main.cc")
set(_mechgen_tool_text [=[
// A tool of a model, defined by mechgen_add_model() (cmake/MechgenAddModel.cmake): the tool's
// own main (MECHGEN_TOOL_MAIN) when the model has what the tool needs (MECHGEN_TOOL_NEEDS, the
// manifest's MECHGEN_MODEL_TOOL_<TOOL>, written by `mechgen generate --manifest`), else a stub
// that says what the model lacks (MECHGEN_TOOL_QUANTITY: the manifest's
// MECHGEN_MODEL_TOOL_<TOOL>_QUANTITY) and exits with status 2.
#include MECHGEN_MODEL_MANIFEST
#if MECHGEN_TOOL_NEEDS
#include MECHGEN_TOOL_MAIN
#else
#include <cstdio>
int main() {
  std::fprintf(stderr,
               "error: the model '%s' was generated without `%s` (its quantities: %s), which its %s tool "
               "needs; add `%s` to its outputs' quantities\n",
               MECHGEN_MODEL_NAME, MECHGEN_TOOL_QUANTITY, MECHGEN_MODEL_QUANTITIES, MECHGEN_TOOL_NAME,
               MECHGEN_TOOL_QUANTITY);
  return 2;
}
#endif
]=])
# Written only when it changes (a rewrite would rebuild every tool).
set(_mechgen_tool_old "")
if(EXISTS "${_MECHGEN_TOOL_SOURCE}")
  file(READ "${_MECHGEN_TOOL_SOURCE}" _mechgen_tool_old)
endif()
if(NOT _mechgen_tool_old STREQUAL _mechgen_tool_text)
  file(WRITE "${_MECHGEN_TOOL_SOURCE}" "${_mechgen_tool_text}")
endif()
unset(_mechgen_tool_old)
unset(_mechgen_tool_text)

# <name>_<tool> from runtime/tools/<tool>_main.cc: real when the manifest's macro
# MECHGEN_MODEL_TOOL_<TOOL> is 1, else the stub that names the quantity to add (the
# manifest's MECHGEN_MODEL_TOOL_<TOOL>_QUANTITY).
function(_mechgen_add_tool name tool)
  set(out_dir "${CMAKE_CURRENT_BINARY_DIR}/mechgen_${name}")
  string(TOUPPER "MECHGEN_MODEL_TOOL_${tool}" need)
  add_executable(${name}_${tool} "${_MECHGEN_TOOL_SOURCE}" "${out_dir}/${name}_manifest.h")
  target_compile_definitions(${name}_${tool} PRIVATE
    MECHGEN_MODEL_INCLUDE="${name}.h" MECHGEN_MODEL_NAMESPACE=mech::${name}
    MECHGEN_MODEL_MANIFEST="${name}_manifest.h" MECHGEN_TOOL_MAIN="${MECHGEN_TOOLS_DIR}/${tool}_main.cc"
    MECHGEN_TOOL_NEEDS=${need} MECHGEN_TOOL_QUANTITY=${need}_QUANTITY MECHGEN_TOOL_NAME="${tool}")
  target_link_libraries(${name}_${tool} PRIVATE mechgen_model_${name} ${ARGN})
  target_compile_options(${name}_${tool} PRIVATE ${MECHGEN_TOOL_COMPILE_OPTIONS})
  set_property(GLOBAL APPEND PROPERTY MECHGEN_MODEL_TOOLS ${name}_${tool})
  # The manifest's macro that makes it the real tool (read by tests/generator's tool test).
  set_property(TARGET ${name}_${tool} PROPERTY MECHGEN_TOOL_NEEDS ${need})
  # CLI11 (header-only): where the build tree found it (runtime/CMakeLists.txt), else on the
  # default include path.
  if(MECHGEN_CLI11_INCLUDE_DIR)
    target_include_directories(${name}_${tool} SYSTEM PRIVATE "${MECHGEN_CLI11_INCLUDE_DIR}")
  endif()
  _mechgen_link_tool_args(${name}_${tool})
endfunction()

# In mechgen's own build tree the tools' option parsers (runtime/tools/<tool>_args.cc, the same
# for every model) are compiled once, into mechgen_tool_args (generator/CMakeLists.txt): each
# tool links them instead of compiling CLI11's part again (the 17 tools the test suite builds:
# 551 -> 305 s of compile jobs). Elsewhere (find_package(mechgen)) the tool's main includes them.
function(_mechgen_link_tool_args target)
  if(TARGET mechgen_tool_args)
    target_compile_definitions(${target} PRIVATE MECHGEN_TOOL_ARGS_SEPARATE)
    target_link_libraries(${target} PRIVATE mechgen_tool_args)
  endif()
endfunction()

# In mechgen_add_model: whether to define the tool `var` (sets it): asked for (`force`), or
# not refused (`refuse`) and the model's tools unknown or `var` among them.
macro(_mechgen_wants var force refuse)
  set(${var} FALSE)
  if(${force})
    set(${var} TRUE)
  elseif(NOT ${refuse} AND (NOT tools_known OR "${var}" IN_LIST tools))
    set(${var} TRUE)
  endif()
endmacro()

function(mechgen_add_model name model)
  # <name> becomes target names, a directory, the files <name>.h/.cc and (via --name) the
  # namespace mech::<name>: a C++ identifier only (mechgen checks the rest: keywords,
  # reserved names, macros; see Names in models/README.md).
  if(NOT name MATCHES "^[A-Za-z][A-Za-z0-9_]*$" OR name MATCHES "__" OR name MATCHES "_$")
    string(REGEX REPLACE "[^A-Za-z0-9]+" "_" suggestion "${name}")
    string(REGEX REPLACE "^_+|_+$" "" suggestion "${suggestion}")
    message(FATAL_ERROR "mechgen_add_model: the name '${name}' is not a C++ identifier "
      "(ASCII letters, digits and single underscores, beginning with a letter and not ending "
      "with '_'); it becomes the namespace mech::<name> and the files <name>.h/.cc. Rename it "
      "(for example ${suggestion}).")
  endif()
  cmake_parse_arguments(ARG "NO_SWEEP;STATICS;NO_STATICS;SIMULATE;NO_SIMULATE;ENGINE;FLYWHEEL" "STRATEGY" ""
                        ${ARGN})
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "mechgen_add_model(${name}): unknown arguments ${ARG_UNPARSED_ARGUMENTS}; "
      "the options are NO_SWEEP, STATICS, NO_STATICS, SIMULATE, NO_SIMULATE, ENGINE, FLYWHEEL, STRATEGY")
  endif()
  set(strategy_args)
  if(ARG_STRATEGY)
    set(strategy_args --strategy ${ARG_STRATEGY})
  endif()
  get_filename_component(model_abs "${model}" ABSOLUTE)
  set(out_dir "${CMAKE_CURRENT_BINARY_DIR}/mechgen_${name}")
  set(manifest "${out_dir}/${name}_manifest.h")
  file(GLOB templates CONFIGURE_DEPENDS "${MECHGEN_TEMPLATES_DIR}/*.mustache")
  set(gen_deps "${model_abs}" ${templates})
  if(TARGET mechgen)
    list(APPEND gen_deps mechgen)
  endif()
  add_custom_command(
    OUTPUT "${out_dir}/${name}.h" "${out_dir}/${name}.cc" "${out_dir}/${name}_view.cc" "${manifest}"
    COMMAND "${MECHGEN_EXECUTABLE}" generate "${model_abs}" --name "${name}"
            --out-dir "${out_dir}" --templates "${MECHGEN_TEMPLATES_DIR}" ${strategy_args}
            --manifest "${manifest}"
    DEPENDS ${gen_deps}
    COMMENT "mechgen: generating ${name} from ${model}"
    VERBATIM)
  # <name>_view.cc: the model view, mech::<name>::View() (mechgen/core/model_view.h, from
  # mechgen::runtime's include directory: standard library only).
  add_library(mechgen_model_${name} STATIC "${out_dir}/${name}.cc" "${out_dir}/${name}.h"
                                           "${out_dir}/${name}_view.cc")
  add_library(mechgen::model_${name} ALIAS mechgen_model_${name})
  target_include_directories(mechgen_model_${name} PUBLIC "${out_dir}")
  target_link_libraries(mechgen_model_${name} PUBLIC Eigen3::Eigen mechgen::runtime)
  target_compile_features(mechgen_model_${name} PUBLIC cxx_std_17)
  if(ARG_NO_SWEEP OR NOT MECHGEN_BUILD_SWEEPS)
    return()
  endif()

  # The model's tools, from the installed generator at configure time; in the build tree (no
  # mechgen to run yet) unknown here: every tool is defined and the manifest decides.
  set(tools_known FALSE)
  set(tools)
  if(NOT TARGET mechgen AND TARGET mechgen::mechgen)
    get_target_property(mechgen_now mechgen::mechgen LOCATION)
    execute_process(
      COMMAND "${mechgen_now}" generate "${model_abs}" --name "${name}" --print-tools
      RESULT_VARIABLE status OUTPUT_VARIABLE printed ERROR_VARIABLE error
      OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_STRIP_TRAILING_WHITESPACE)
    if(NOT status EQUAL 0)
      message(FATAL_ERROR "mechgen_add_model(${name}): ${error}")
    endif()
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${model_abs}" "${mechgen_now}")
    separate_arguments(tools UNIX_COMMAND "${printed}")
    set(tools_known TRUE)
  endif()

  if(TARGET mechgen::runtime_ceres AND EXISTS "${MECHGEN_TOOLS_DIR}/sweep_main.cc")
    add_executable(${name}_sweep "${MECHGEN_TOOLS_DIR}/sweep_main.cc")
    target_compile_definitions(${name}_sweep PRIVATE
      MECHGEN_MODEL_INCLUDE="${name}.h" MECHGEN_MODEL_NAMESPACE=mech::${name})
    target_link_libraries(${name}_sweep PRIVATE mechgen_model_${name} mechgen::runtime_ceres)
    target_compile_options(${name}_sweep PRIVATE ${MECHGEN_TOOL_COMPILE_OPTIONS})
    _mechgen_link_tool_args(${name}_sweep)
    set_property(GLOBAL APPEND PROPERTY MECHGEN_MODEL_TOOLS ${name}_sweep)
    _mechgen_wants(statics ARG_STATICS ARG_NO_STATICS)
    if(statics AND EXISTS "${MECHGEN_TOOLS_DIR}/statics_main.cc")
      _mechgen_add_tool(${name} statics mechgen::runtime_ceres)
      # Where `--plots` finds plot_statics.gnuplot and plot_bearings.gnuplot.
      target_compile_definitions(${name}_statics PRIVATE MECHGEN_TOOLS_DIR="${MECHGEN_TOOLS_DIR}")
    endif()
  endif()
  _mechgen_wants(simulate ARG_SIMULATE ARG_NO_SIMULATE)
  if(simulate AND EXISTS "${MECHGEN_TOOLS_DIR}/simulate_main.cc")
    _mechgen_add_tool(${name} simulate mechgen::runtime)
  endif()
  if(ARG_ENGINE AND EXISTS "${MECHGEN_TOOLS_DIR}/engine_main.cc")
    _mechgen_add_tool(${name} engine mechgen::runtime)
  endif()
  if(ARG_FLYWHEEL AND EXISTS "${MECHGEN_TOOLS_DIR}/flywheel_main.cc")
    _mechgen_add_tool(${name} flywheel mechgen::runtime)
  endif()
endfunction()

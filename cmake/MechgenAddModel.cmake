# mechgen_add_model(<name> <model.yaml> [NO_SWEEP] [STATICS|NO_STATICS]
#                   [SIMULATE|NO_SIMULATE] [ENGINE] [STRATEGY blocks|monolithic])
#
# Runs `mechgen generate` on <model.yaml> at build time (again whenever the model, the
# templates or the mechgen program change) and defines:
#   mechgen_model_<name>   a static library (alias mechgen::model_<name>) whose include
#                          directory holds <name>.h; link a product against it.
#   <name>_sweep           unless NO_SWEEP, MECHGEN_BUILD_SWEEPS is OFF, or Ceres is absent
#                          (no target mechgen::runtime_ceres): the sweep command of the
#                          runtime for this model. It assembles with Ceres.
#   <name>_statics         under the same conditions, for a model whose outputs ask for
#                          `forces` (its `quantities:` list, read from the model file at
#                          configure time; STATICS forces it, NO_STATICS skips it): the statics
#                          command (runtime/tools/statics_main.cc; driving forces, reactions,
#                          dead zones, equilibria; CSV, SVG). A model without statics builds
#                          into a stub that says so.
#   <name>_simulate        unless NO_SWEEP or MECHGEN_BUILD_SWEEPS is OFF (Ceres not needed),
#                          for a model whose outputs ask for `dynamics` (read like `forces`;
#                          SIMULATE forces it, NO_SIMULATE skips it): the forward-dynamics
#                          command (runtime/tools/simulate_main.cc; a transient to a steady
#                          state, CSV for runtime/tools/plot_dynamics.gnuplot).
#   <name>_engine          with ENGINE (a model made by tools/make_engine.py), unless NO_SWEEP
#                          or MECHGEN_BUILD_SWEEPS is OFF: the engine command
#                          (runtime/tools/engine_main.cc; crank torque over a cycle, bearing
#                          loads, flywheel sizing, run-up; CSV for tools/plot_engine.gnuplot).
# The model library needs Eigen only; with NO_SWEEP nothing here needs Ceres.
# Requires MECHGEN_EXECUTABLE and MECHGEN_TEMPLATES_DIR (set by the build tree or by
# find_package(mechgen)).
include_guard(GLOBAL)

# OFF skips every <model>_sweep tool (e.g. the sanitizer build: one executable per model
# that no test runs).
option(MECHGEN_BUILD_SWEEPS "Build the <model>_sweep tool of each mechgen_add_model()" ON)

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
  cmake_parse_arguments(ARG "NO_SWEEP;STATICS;NO_STATICS;SIMULATE;NO_SIMULATE;ENGINE" "STRATEGY" ""
                        ${ARGN})
  set(strategy_args)
  if(ARG_STRATEGY)
    set(strategy_args --strategy ${ARG_STRATEGY})
  endif()
  get_filename_component(model_abs "${model}" ABSOLUTE)
  set(out_dir "${CMAKE_CURRENT_BINARY_DIR}/mechgen_${name}")
  file(GLOB templates CONFIGURE_DEPENDS "${MECHGEN_TEMPLATES_DIR}/*.mustache")
  set(gen_deps "${model_abs}" ${templates})
  if(TARGET mechgen)
    list(APPEND gen_deps mechgen)
  endif()
  add_custom_command(
    OUTPUT "${out_dir}/${name}.h" "${out_dir}/${name}.cc"
    COMMAND "${MECHGEN_EXECUTABLE}" generate "${model_abs}" --name "${name}"
            --out-dir "${out_dir}" --templates "${MECHGEN_TEMPLATES_DIR}" ${strategy_args}
    DEPENDS ${gen_deps}
    COMMENT "mechgen: generating ${name} from ${model}"
    VERBATIM)
  add_library(mechgen_model_${name} STATIC "${out_dir}/${name}.cc" "${out_dir}/${name}.h")
  add_library(mechgen::model_${name} ALIAS mechgen_model_${name})
  target_include_directories(mechgen_model_${name} PUBLIC "${out_dir}")
  target_link_libraries(mechgen_model_${name} PUBLIC Eigen3::Eigen)
  target_compile_features(mechgen_model_${name} PUBLIC cxx_std_17)
  if(NOT ARG_NO_SWEEP AND MECHGEN_BUILD_SWEEPS AND TARGET mechgen::runtime_ceres
     AND EXISTS "${MECHGEN_TOOLS_DIR}/sweep_main.cc")
    add_executable(${name}_sweep "${MECHGEN_TOOLS_DIR}/sweep_main.cc")
    target_compile_definitions(${name}_sweep PRIVATE
      MECHGEN_MODEL_INCLUDE="${name}.h" MECHGEN_MODEL_NAMESPACE=mech::${name})
    target_link_libraries(${name}_sweep PRIVATE mechgen_model_${name} mechgen::runtime_ceres)
    # Statics: `forces` among the model's quantities, flow (`quantities: [K, forces]`) or
    # block style (`quantities:` then `- forces` lines).
    set(statics ${ARG_STATICS})
    if(NOT ARG_STATICS AND NOT ARG_NO_STATICS)
      set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${model_abs}")
      file(READ "${model_abs}" model_text)
      if(model_text MATCHES "quantities:[ \t]*\\[[^\n]*forces"
         OR model_text MATCHES "quantities:[ \t]*\n([ \t]+-[^\n]*\n)*[ \t]+-[ \t]*forces")
        set(statics TRUE)
      endif()
    endif()
    if(statics AND EXISTS "${MECHGEN_TOOLS_DIR}/statics_main.cc")
      add_executable(${name}_statics "${MECHGEN_TOOLS_DIR}/statics_main.cc")
      target_compile_definitions(${name}_statics PRIVATE
        MECHGEN_MODEL_INCLUDE="${name}.h" MECHGEN_MODEL_NAMESPACE=mech::${name})
      target_link_libraries(${name}_statics PRIVATE mechgen_model_${name}
                            mechgen::runtime_ceres)
    endif()
  endif()
  # Dynamics: `dynamics` among the model's quantities (as for `forces` above). Eigen only.
  if(NOT ARG_NO_SWEEP AND MECHGEN_BUILD_SWEEPS AND EXISTS "${MECHGEN_TOOLS_DIR}/simulate_main.cc")
    set(simulate ${ARG_SIMULATE})
    if(NOT ARG_SIMULATE AND NOT ARG_NO_SIMULATE)
      set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${model_abs}")
      file(READ "${model_abs}" model_text)
      if(model_text MATCHES "quantities:[ \t]*\\[[^\n]*dynamics"
         OR model_text MATCHES "quantities:[ \t]*\n([ \t]+-[^\n]*\n)*[ \t]+-[ \t]*dynamics")
        set(simulate TRUE)
      endif()
    endif()
    if(simulate)
      add_executable(${name}_simulate "${MECHGEN_TOOLS_DIR}/simulate_main.cc")
      target_compile_definitions(${name}_simulate PRIVATE
        MECHGEN_MODEL_INCLUDE="${name}.h" MECHGEN_MODEL_NAMESPACE=mech::${name})
      target_link_libraries(${name}_simulate PRIVATE mechgen_model_${name} mechgen::runtime)
    endif()
  endif()
  if(ARG_ENGINE AND NOT ARG_NO_SWEEP AND MECHGEN_BUILD_SWEEPS
     AND EXISTS "${MECHGEN_TOOLS_DIR}/engine_main.cc")
    add_executable(${name}_engine "${MECHGEN_TOOLS_DIR}/engine_main.cc")
    target_compile_definitions(${name}_engine PRIVATE
      MECHGEN_MODEL_INCLUDE="${name}.h" MECHGEN_MODEL_NAMESPACE=mech::${name})
    target_link_libraries(${name}_engine PRIVATE mechgen_model_${name} mechgen::runtime)
    # Its command line is parsed with CLI11 (header-only): where the build tree found it
    # (runtime/CMakeLists.txt), else on the default include path.
    if(MECHGEN_CLI11_INCLUDE_DIR)
      target_include_directories(${name}_engine SYSTEM PRIVATE "${MECHGEN_CLI11_INCLUDE_DIR}")
    endif()
  endif()
endfunction()

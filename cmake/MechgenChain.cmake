# mechgen_add_chain(<N> [STRATEGY blocks|monolithic])
# The scaling model of N four-bar loops in series (tools/make_chain.sh), generated at build
# time: target mechgen_model_chain_<N> (or mechgen_model_chain_<N>_monolithic), namespace
# mech::chain_<N>[_monolithic]. For tests and benchmarks inside this tree; not installed.
function(mechgen_add_chain n)
  cmake_parse_arguments(ARG "" "STRATEGY" "" ${ARGN})
  set(name chain_${n})
  set(strategy blocks)
  if(ARG_STRATEGY STREQUAL "monolithic")
    set(name chain_${n}_monolithic)
    set(strategy monolithic)
  endif()
  if(TARGET mechgen_model_${name})
    return()
  endif()
  set(yaml ${CMAKE_BINARY_DIR}/chains/${name}.yaml)
  add_custom_command(OUTPUT ${yaml}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_BINARY_DIR}/chains
    COMMAND bash ${PROJECT_SOURCE_DIR}/tools/make_chain.sh ${n} 2 ${yaml}
    DEPENDS ${PROJECT_SOURCE_DIR}/tools/make_chain.sh
    COMMENT "make_chain.sh ${n}" VERBATIM)
  mechgen_add_model(${name} ${yaml} NO_SWEEP STRATEGY ${strategy})
  # Monolithic fixed-size matrices of large chains exceed Eigen's default stack limit.
  target_compile_definitions(mechgen_model_${name} PUBLIC EIGEN_STACK_ALLOCATION_LIMIT=0)
endfunction()

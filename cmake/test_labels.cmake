# Every test gets one CTest label, so that `ctest -L unit` runs in seconds
# (docs/architecture.md "Which tests to run"):
#   unit         no GL driver, no socket, no other process: seconds
#   integration  a real driver (EGL, OSMesa) or real ZeroMQ sockets, in one process
#   e2e          programs and glcast processes, under Xvfb or across network namespaces
# Tests that gtest_discover_tests finds are labelled where they are discovered (PROPERTIES
# LABELS); glcast_label_directory_tests labels the add_test tests of the calling directory: the
# names listed as UNIT or INTEGRATION get those labels, every other one e2e.
function(glcast_label_directory_tests)
  cmake_parse_arguments(ARG "" "" "UNIT;INTEGRATION" ${ARGN})
  get_property(_tests DIRECTORY PROPERTY TESTS)
  foreach(_test IN LISTS _tests)
    if(_test IN_LIST ARG_UNIT)
      set(_label unit)
    elseif(_test IN_LIST ARG_INTEGRATION)
      set(_label integration)
    else()
      set(_label e2e)
    endif()
    set_tests_properties(${_test} PROPERTIES LABELS ${_label})
  endforeach()
endfunction()

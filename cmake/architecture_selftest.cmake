cmake_minimum_required(VERSION 3.22)
# Runs the architecture rule on given edges: cmake -DTARGET=x -DLINKS="a;b" -P this.
# Exits with an error when an edge is forbidden (tests/architecture uses it both ways).
include(${CMAKE_CURRENT_LIST_DIR}/architecture.cmake)
rangekit_forbidden_links(${TARGET} "${LINKS}" violations)
if(violations)
  message(FATAL_ERROR "architecture: ${TARGET} links ${violations}, which it must not")
endif()
message(STATUS "architecture: ${TARGET} -> ${LINKS}: allowed")

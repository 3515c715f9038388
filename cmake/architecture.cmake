# Which rangekit library may link which (docs/architecture.md). Checked at
# configure time: a library that links one it must not stops the configure.
# The rule table is data so that tests/architecture can run the same check on
# a table with a forbidden edge and see it fail (cmake -P architecture_selftest.cmake).

# The families (families.cmake), whose rows below follow one rule each; the self-test includes
# this file alone, so it reads the list itself.
include(${CMAKE_CURRENT_LIST_DIR}/../families.cmake)

# rangekit_allowed_links_<target>: the rangekit libraries <target> may link.
set(rangekit_allowed_links_rangekit_core "")
set(rangekit_allowed_links_rangekit_record rangekit_core)
set(rangekit_allowed_links_rangekit_sim rangekit_core)  # and each family's codec, below
set(rangekit_allowed_links_rangekit_hub rangekit_core rangekit_record)  # no family: they register with it
# A face reaches the sensors only through the hub: never a family's library itself.
set(rangekit_allowed_links_rangekit_web rangekit_hub rangekit_core rangekit_record)
set(rangekit_allowed_links_rangekit_mqtt rangekit_hub rangekit_core rangekit_record)
set(rangekit_allowed_links_rangekit_modbus rangekit_hub rangekit_core)
set(rangekit_allowed_links_rangekit_sinks rangekit_hub rangekit_core rangekit_record)
set(rangekit_known_libraries rangekit_core rangekit_record rangekit_sim rangekit_hub rangekit_web rangekit_mqtt
  rangekit_modbus rangekit_sinks)
foreach(family IN LISTS RANGEKIT_FAMILIES)
  # A family's codec and driver: core only, never another family, never sim (an embedder links no emulator).
  set(rangekit_allowed_links_rangekit_${family} rangekit_core)
  # Its service part: the hub and its own family, never another's, never sim (a site's sensors are real).
  set(rangekit_allowed_links_rangekit_${family}_service rangekit_hub rangekit_${family} rangekit_core)
  # The emulators drive each family's firmware model with its codec.
  list(APPEND rangekit_allowed_links_rangekit_sim rangekit_${family})
  list(APPEND rangekit_known_libraries rangekit_${family} rangekit_${family}_service)
endforeach()

# Checks one library's links (`links`: what it links, any kind of entry) against
# its allowed list; returns the offending rangekit libraries in `out_violations`.
function(rangekit_forbidden_links target links out_violations)
  set(violations "")
  foreach(link IN LISTS links)
    # $<LINK_ONLY:x>, $<BUILD_INTERFACE:x> and rangekit::x all name x.
    string(REGEX REPLACE "^\\$<[A-Z_]+:(.*)>$" "\\1" link "${link}")
    string(REGEX REPLACE "^rangekit::" "rangekit_" link "${link}")
    if(NOT link IN_LIST rangekit_known_libraries)
      continue()  # third-party or build-only (warnings) targets
    endif()
    if(NOT link IN_LIST rangekit_allowed_links_${target})
      list(APPEND violations ${link})
    endif()
  endforeach()
  set(${out_violations} "${violations}" PARENT_SCOPE)
endfunction()

function(rangekit_check_architecture)
  foreach(target IN ITEMS ${ARGN})
    if(NOT DEFINED rangekit_allowed_links_${target})
      message(FATAL_ERROR "architecture: ${target} has no row in cmake/architecture.cmake")
    endif()
    get_target_property(private_links ${target} LINK_LIBRARIES)
    get_target_property(interface_links ${target} INTERFACE_LINK_LIBRARIES)
    set(links "")
    foreach(list IN ITEMS private_links interface_links)
      if(${list})
        list(APPEND links ${${list}})
      endif()
    endforeach()
    rangekit_forbidden_links(${target} "${links}" violations)
    if(violations)
      message(FATAL_ERROR "architecture: ${target} links ${violations}, which it must not "
                          "(allowed: ${rangekit_allowed_links_${target}}; see docs/architecture.md)")
    endif()
  endforeach()
endfunction()

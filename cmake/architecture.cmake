# Which rangekit library may link which (docs/architecture.md). Checked at
# configure time: a library that links one it must not stops the configure.
# The rule table is data so that tests/architecture can run the same check on
# a table with a forbidden edge and see it fail (cmake -P architecture_selftest.cmake).

# rangekit_allowed_links_<target>: the rangekit libraries <target> may link.
set(rangekit_allowed_links_rangekit_core "")
set(rangekit_allowed_links_rangekit_uls rangekit_core)
set(rangekit_allowed_links_rangekit_ls5 rangekit_core)
set(rangekit_allowed_links_rangekit_record rangekit_core)
set(rangekit_allowed_links_rangekit_sim rangekit_core rangekit_uls rangekit_ls5)
set(rangekit_allowed_links_rangekit_hub rangekit_core rangekit_record)  # no family: they register with it
# A family's service part: the hub and its own family, never another's, never sim (a site's sensors are real).
set(rangekit_allowed_links_rangekit_uls_service rangekit_hub rangekit_uls rangekit_core)
set(rangekit_allowed_links_rangekit_ls5_service rangekit_hub rangekit_ls5 rangekit_core)
# A face reaches the sensors only through the hub: never a driver (uls, ls5) itself.
set(rangekit_allowed_links_rangekit_web rangekit_hub rangekit_core rangekit_record)
set(rangekit_allowed_links_rangekit_mqtt rangekit_hub rangekit_core rangekit_record)

# Checks one library's links (`links`: what it links, any kind of entry) against
# its allowed list; returns the offending rangekit libraries in `out_violations`.
function(rangekit_forbidden_links target links out_violations)
  set(violations "")
  foreach(link IN LISTS links)
    # $<LINK_ONLY:x>, $<BUILD_INTERFACE:x> and rangekit::x all name x.
    string(REGEX REPLACE "^\\$<[A-Z_]+:(.*)>$" "\\1" link "${link}")
    string(REGEX REPLACE "^rangekit::" "rangekit_" link "${link}")
    if(NOT link MATCHES "^rangekit_(core|uls|ls5|record|sim|hub|web|mqtt|uls_service|ls5_service)$")
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

# Read by ctest after the web tests are discovered: the tests that drive a site of emulators
# hard (hundreds of clients, requests without pause) count as three of ctest's slots, so that
# fewer tests share the CPU with them. Beside them at six at once, pty tests of other
# binaries missed their deadlines (an LS5 reply over 500 ms, a measurement over 15 s).
if(rangekit_web_tests_TESTS)
  foreach(test IN LISTS rangekit_web_tests_TESTS)
    if(test MATCHES "^(AccessTable|HostileClient)[.]")
      set_tests_properties(${test} PROPERTIES PROCESSORS 3)
    endif()
  endforeach()
endif()

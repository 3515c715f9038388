# The browser dashboard (web/, docs/dashboard.md), bundled by esbuild in BUILD/web and
# embedded in the CLI by embed_assets.cmake. Sets RANGEKIT_DASHBOARD_SOURCE (the generated
# .cpp) and RANGEKIT_DASHBOARD_DIR (the build's copy of web/, with the generated
# src/registered_families.ts, RANGEKIT_FAMILIES_TS, beside families.ts).
set(RANGEKIT_DASHBOARD_SOURCE ${PROJECT_BINARY_DIR}/generated/dashboard_assets.cpp)
set(RANGEKIT_DASHBOARD_DIR ${PROJECT_BINARY_DIR}/web)
if(NOT RANGEKIT_DASHBOARD)
  message(STATUS "rangekit serve without the dashboard (RANGEKIT_DASHBOARD=OFF): '/' answers 404")
  execute_process(COMMAND ${CMAKE_COMMAND} -DEMPTY=ON -DOUTPUT=${RANGEKIT_DASHBOARD_SOURCE}
                          -P ${PROJECT_SOURCE_DIR}/cmake/embed_assets.cmake COMMAND_ERROR_IS_FATAL ANY)
  return()
endif()

find_program(RANGEKIT_NODE node)
find_program(RANGEKIT_NPM npm)
if(NOT RANGEKIT_NODE OR NOT RANGEKIT_NPM)
  message(FATAL_ERROR "The dashboard (web/) is built with node and npm, and they were not found. "
                      "Install them with `bash scripts/install-deps.sh build` (Debian's nodejs and npm; "
                      "`make build` does it), or configure with -DRANGEKIT_DASHBOARD=OFF for a rangekit serve "
                      "without the dashboard.")
endif()
execute_process(COMMAND ${RANGEKIT_NODE} --version OUTPUT_VARIABLE node_version OUTPUT_STRIP_TRAILING_WHITESPACE)
if(node_version VERSION_LESS "v18")
  message(FATAL_ERROR "The dashboard's toolchain (esbuild, TypeScript) needs node 18 or later; ${RANGEKIT_NODE} is ${node_version}")
endif()

set(web ${PROJECT_SOURCE_DIR}/web)
file(GLOB_RECURSE web_sources CONFIGURE_DEPENDS ${web}/src/* ${web}/tests/*)
set(web_files ${web}/index.html ${web}/build.mjs ${web}/tsconfig.json)
file(MAKE_DIRECTORY ${RANGEKIT_DASHBOARD_DIR})  # the commands below run in it
set(npm_stamp ${RANGEKIT_DASHBOARD_DIR}/node_modules/.rangekit-npm-ci)
add_custom_command(OUTPUT ${npm_stamp}
  COMMAND ${CMAKE_COMMAND} -E copy ${web}/package.json ${web}/package-lock.json ${RANGEKIT_DASHBOARD_DIR}
  COMMAND ${RANGEKIT_NPM} ci --no-audit --no-fund --loglevel=error
  COMMAND ${CMAKE_COMMAND} -E touch ${npm_stamp}
  WORKING_DIRECTORY ${RANGEKIT_DASHBOARD_DIR}
  DEPENDS ${web}/package.json ${web}/package-lock.json
  COMMENT "npm ci: the dashboard's toolchain from web/package-lock.json"
  VERBATIM)
add_custom_command(OUTPUT ${RANGEKIT_DASHBOARD_SOURCE}
  COMMAND ${CMAKE_COMMAND} -E rm -rf ${RANGEKIT_DASHBOARD_DIR}/src ${RANGEKIT_DASHBOARD_DIR}/tests
          ${RANGEKIT_DASHBOARD_DIR}/dist
  COMMAND ${CMAKE_COMMAND} -E copy_directory ${web}/src ${RANGEKIT_DASHBOARD_DIR}/src
  COMMAND ${CMAKE_COMMAND} -E copy ${RANGEKIT_FAMILIES_TS} ${RANGEKIT_DASHBOARD_DIR}/src
  COMMAND ${CMAKE_COMMAND} -E copy_directory ${web}/tests ${RANGEKIT_DASHBOARD_DIR}/tests
  COMMAND ${CMAKE_COMMAND} -E copy ${web_files} ${RANGEKIT_DASHBOARD_DIR}
  COMMAND ${RANGEKIT_NPM} run --silent build
  COMMAND ${CMAKE_COMMAND} -DDIST=${RANGEKIT_DASHBOARD_DIR}/dist -DOUTPUT=${RANGEKIT_DASHBOARD_SOURCE}
          -P ${PROJECT_SOURCE_DIR}/cmake/embed_assets.cmake
  WORKING_DIRECTORY ${RANGEKIT_DASHBOARD_DIR}
  DEPENDS ${npm_stamp} ${web_sources} ${web_files} ${RANGEKIT_FAMILIES_TS} ${PROJECT_SOURCE_DIR}/cmake/embed_assets.cmake
  COMMENT "Building the dashboard (tsc, esbuild) and embedding it"
  VERBATIM)

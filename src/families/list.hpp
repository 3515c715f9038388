// The registration list: every family rangekit builds, one line each. A family `name` is the
// folder src/name, the namespace rangekit::name and the site file's and samples' "name"; each
// layer's registration (registered*.cpp) expands this list and names no family itself.
#pragma once

#define RANGEKIT_FAMILIES(FAMILY) \
  FAMILY(uls)                     \
  FAMILY(ls5)

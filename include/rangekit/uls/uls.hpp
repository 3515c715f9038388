// Everything of the ULS codec in one include.
#pragma once

#include "rangekit/uls/commands.hpp"
#include "rangekit/uls/errors.hpp"
#include "rangekit/uls/formulas.hpp"
#include "rangekit/uls/frame.hpp"
#include "rangekit/uls/measurement.hpp"
#include "rangekit/uls/reply.hpp"
#include "rangekit/uls/types.hpp"

// Everything of the LS5 codec in one include.
#pragma once

#include "rangekit/ls5/commands.hpp"
#include "rangekit/ls5/fixed_text.hpp"
#include "rangekit/ls5/formulas.hpp"
#include "rangekit/ls5/frame.hpp"
#include "rangekit/ls5/identification.hpp"
#include "rangekit/ls5/logical_values.hpp"
#include "rangekit/ls5/parameters.hpp"
#include "rangekit/ls5/reply.hpp"
#include "rangekit/ls5/request.hpp"
#include "rangekit/ls5/result_code.hpp"
#include "rangekit/ls5/settings.hpp"
#include "rangekit/ls5/udp_packet.hpp"
#include "rangekit/ls5/version.hpp"

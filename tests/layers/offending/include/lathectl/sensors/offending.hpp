#pragma once
// A core header that includes one of a higher core folder: layer_order.cmake must fail on this
// tree (the test layers_order_detects).
#include "lathectl/control/offending.hpp"

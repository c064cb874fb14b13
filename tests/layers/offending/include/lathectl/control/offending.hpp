#pragma once
// A core header that includes a host one: core_includes.cmake must fail on this tree
// (the test core_layers_detects).
#include "lathectl/sim/recorder.hpp"

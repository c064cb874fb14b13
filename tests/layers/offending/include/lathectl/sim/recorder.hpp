#pragma once
// A host header the core must not include (tests/layers/offending).

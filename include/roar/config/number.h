#pragma once
// A number a person typed (a CSV cell, a command-line value): the whole text must be one number, so that
// "2x" is an error rather than 2.
#include <string>

namespace roar::config {

// True when all of `text` is one number as strtod reads it ("nan" and "inf" included: callers that need a
// finite one say so themselves); the number in *value.
bool parseNumber(const std::string& text, double* value);

}  // namespace roar::config

#pragma once
// A number a person typed (a CSV cell, a command-line value): the whole text must be one number, so that
// "2x" is an error rather than 2.
#include <climits>
#include <string>

namespace roar::config {

// True when all of `text` is one number as strtod reads it ("nan" and "inf" included: callers that need a
// finite one say so themselves); the number in *value.
bool parseNumber(const std::string& text, double* value);

// `text`, typed for the option `name`, as a finite number; otherwise throws std::invalid_argument
// "<name> '<text>' is not a number".
double numberArgument(const std::string& name, const std::string& text);
// The same as a whole number in [low, high]; otherwise throws std::invalid_argument naming the option and
// the range.
long long wholeNumberArgument(const std::string& name, const std::string& text, long long low,
                              long long high = INT_MAX);

// Whether a command line asks for help (--help or -h anywhere): the tools then print their usage on
// standard output and exit 0.
bool helpRequested(int argc, char** argv);

}  // namespace roar::config

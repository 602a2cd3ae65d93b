// Standard output as a data channel (`--json -`): once reserved, stdout carries only the data written through
// write_standard_output, and everything else the program prints to stdout lands on stderr, so a pipe into a JSON
// parser never sees a human line.
#pragma once

#include <string_view>

namespace prism {

// Moves the current stdout aside for data and points stdout at stderr. Call before anything is printed.
void reserve_standard_output_for_data();
// From now on stdout (the human text) goes nowhere; data reserved above still reaches the real stdout.
void silence_standard_output();
// Writes to the real standard output (the reserved one when reserved). Throws prism::Error on a write failure.
void write_standard_output(std::string_view bytes);

}  // namespace prism

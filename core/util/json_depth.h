// How deeply a JSON text nests its arrays and objects, found by a scan that needs no stack. tinygltf turns every
// "extras" and "extensions" value into its own Value tree by recursion, so a few KB of "[[[[..." would overflow
// the native stack inside it; the loaders measure the depth before handing text over.
#pragma once

#include <cstddef>
#include <string_view>

namespace prism {

// The deepest nesting of [ and { outside strings (0 for a scalar). Malformed text is measured as far as it goes;
// the parser reports it.
size_t json_nesting_depth(std::string_view text);

}  // namespace prism

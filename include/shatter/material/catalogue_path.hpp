#pragma once
// Where the shipped material catalogue is (kept out of catalogue.hpp, which most of the tree
// includes).

#include <filesystem>

namespace shatter {

// $SHATTER_DATA_DIR/materials.toml when that variable is set; else share/shatter/materials.toml
// beside the running program's bin/ (an installed shatter, `cmake --install`); else the source
// tree's data/materials.toml (a build tree). Throws std::invalid_argument naming the places tried
// when none exists. MaterialCatalogue::builtin() loads this file.
std::filesystem::path builtin_catalogue_path();

}  // namespace shatter

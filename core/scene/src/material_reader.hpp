#pragma once
/// Reading [material] from the contact model's table of parameters (granular/contact_model.hpp):
/// every declared parameter is a key, checked against its declared range (private to the core).
#include <span>
#include <string>

#include "granular/contact_model.hpp"
#include "granular/material.hpp"
#include "toml_table_reader.hpp"

namespace granular {

/// The scene's [material] (defaults where absent); `table` is the model's unless a test adds a
/// term of its own.
Material readMaterial(const TomlTableReader& root, const std::string& file,
                      std::span<const ParameterSpec> table = materialParameters());

}  // namespace granular

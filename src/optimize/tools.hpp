#pragma once
// The tool file (`lathectl optimize --tool-file FILE`) and LinuxCNC's tool table as optimize uses
// them: the one reader is io's (lathectl/io/tool_file.hpp), which the LinuxCNC plant
// (lathectl_plant tool_file=) reads too.

#include "lathectl/io/tool_file.hpp"

namespace lathectl::optimize {

using io::apply_tool_table;
using io::find_tool;
using io::kind_name;
using io::read_tool_file;
using io::read_tool_table;
using io::TableTool;
using io::ToolSpec;

}  // namespace lathectl::optimize

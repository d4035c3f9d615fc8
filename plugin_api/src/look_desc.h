// fl_look_desc <-> firelook::Look (fl_look_create, fl_look_get_desc): the look file's values in plain
// C form, so an editor needs no copy of the look file's schema.
#pragma once

#include <span>
#include <string>

#include "firelook/firelook.h"
#include "look/look.h"

namespace firelook::plugin {

// The look `desc` describes, validated (validateLook: LookError naming source_name). A malformed desc
// (unknown form, null array with a count, unterminated preset name) throws firelook::Error (ErrorCode::InvalidArgument).
Look lookFromDesc(const fl_look_desc& desc, const std::string& source_name);

// The look's form, scalars, preset and counts (pointers null); a preset name longer than the field
// throws firelook::Error (ErrorCode::InvalidArgument) (none is: emission_presets.h).
fl_look_desc descOf(const Look& look);

// The look's arrays into the callers' buffers, each as large as descOf's counts (or empty: not written).
void writeLookArrays(const Look& look, std::span<double> stops, std::span<float> bins, std::span<float> lights);

}  // namespace firelook::plugin

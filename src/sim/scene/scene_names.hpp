// SPDX-License-Identifier: MIT
/// @file
/// The scene format's choices that are not enumerations of the public API, each as an
/// enumeration with one table of names (docs/simulation.md §2): the mesh generators, the
/// solver's `mode`, a contact effect's `length`, and the elastic effects' `model`. The
/// public enumerations' tables are next to them (`kProjectionNames`, `kVolumeProjectionNames`,
/// `kPenaltyNames`, `kShapeNames`, `kBroadPhaseNames`, `kLinearSolverNames`). Internal to
/// pce::sim.
#pragma once

#include <pce/core/enum_names.hpp>

namespace pce::sim {

/// A mesh `generator`'s `type`.
enum class GeneratorKind { grid, strands, tet_box, tet_ball };
/// The names of `GeneratorKind`, in the order the scene format lists them.
inline constexpr EnumNames<GeneratorKind, 4> kGeneratorNames{{
    {GeneratorKind::grid, "grid"},
    {GeneratorKind::strands, "strands"},
    {GeneratorKind::tet_box, "tet_box"},
    {GeneratorKind::tet_ball, "tet_ball"},
}};
/// The table of `GeneratorKind`'s names.
constexpr const EnumNames<GeneratorKind, 4>& enum_names(GeneratorKind) { return kGeneratorNames; }

/// A self-contact effect's `length`: pce::UnsignedLength or pce::SignedLength.
enum class LengthKind { unsigned_length, signed_length };
/// The names of `LengthKind`.
inline constexpr EnumNames<LengthKind, 2> kLengthNames{{
    {LengthKind::unsigned_length, "unsigned"},
    {LengthKind::signed_length, "signed"},
}};
/// The table of `LengthKind`'s names.
constexpr const EnumNames<LengthKind, 2>& enum_names(LengthKind) { return kLengthNames; }

/// The `stretching` effect's `model` (one so far).
enum class StretchingModel { arap };
/// The names of `StretchingModel`.
inline constexpr EnumNames<StretchingModel, 1> kStretchingModelNames{{{StretchingModel::arap, "arap"}}};
/// The table of `StretchingModel`'s names.
constexpr const EnumNames<StretchingModel, 1>& enum_names(StretchingModel) { return kStretchingModelNames; }

/// The `volume_elasticity` effect's `model` (one so far).
enum class VolumeModel { stable_neo_hookean };
/// The names of `VolumeModel`.
inline constexpr EnumNames<VolumeModel, 1> kVolumeModelNames{{{VolumeModel::stable_neo_hookean, "stable_neo_hookean"}}};
/// The table of `VolumeModel`'s names.
constexpr const EnumNames<VolumeModel, 1>& enum_names(VolumeModel) { return kVolumeModelNames; }

}  // namespace pce::sim

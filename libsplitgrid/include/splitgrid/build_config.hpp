#pragma once

#include <array>
#include <cstdint>
#include <string_view>
#include <variant>

namespace sg {

/// Hard upper bound of BuildConfig::max_depth; it sizes the traverser's fixed stack.
inline constexpr std::uint32_t max_supported_depth = 64;

/// Every parameter of the Split Grid builder. Flags of sg-build and sg-bench map one-to-one
/// onto these fields (`--leaf-size` sets leaf_size, and so on). validate() names the field,
/// the value and the valid range of the first bad field. build_config_fields (below) lists
/// every field once, with its range and help: validation, the tools' flags, their JSON and
/// the .sg file's CONF section all go through that table.
///
/// The resolution of a node with n triangles is (see resolution.hpp)
///   N(n) = round(resolution_min + (resolution_max - resolution_min)
///                 * (1 - exp(-(n / resolution_sigma)^2 / 2)))
/// a Gaussian bell turned upside down: few cells when n is small (near the leaves), rising
/// smoothly to resolution_max once n is a few sigma (near the root); then capped by
/// min_cell_width so that cells stay at least as wide as the triangles.
struct BuildConfig {
    /// Fewest cells of an inner node. Range [1, resolution_max]. 2 makes the small nodes
    /// near the leaves binary splits, which the poster describes as "coarse splits".
    std::uint32_t resolution_min = 2;
    /// Most cells of an inner node. Range [max(2, resolution_min), 2^20]. Reached by nodes with
    /// several resolution_sigma triangles, i.e. the top levels. Wide top nodes make every ray
    /// step through many empty cells: in counted work per ray, 16 beats 64 on most scenes (not
    /// on the Stanford dragon, where 32 is best), and it makes fewer references
    /// (docs/notebook/structure.md, "Build parameters under the new kernels").
    std::uint32_t resolution_max = 16;
    /// Width of the Gaussian, in triangles. Range (0, 1e9]. At n = sigma the resolution is
    /// 39% of the way from min to max, at n = 2 sigma 86%, at n = 3 sigma 99%.
    double resolution_sigma = 48.0;
    /// A cell with at most this many triangles becomes a leaf. Range [1, 2^20]. Equidistant
    /// planes cut triangles wherever they fall, so small leaves cost references. The leaf test
    /// reads its references eight at a time, so a full leaf of 16 takes two passes; against 8
    /// it still traced faster, with fewer references and a faster build
    /// (docs/notebook/structure.md, "Leaf size 16 under the lean kernels").
    std::uint32_t leaf_size = 16;
    /// Deepest inner node (the root is depth 0); cells of a node at this depth become leaves.
    /// Range [0, 64]; 64 also bounds the traversal stack.
    std::uint32_t max_depth = 32;
    /// A split makes no progress when two or more cells, or every non-empty cell, would
    /// receive more than this fraction of the node's triangles (triangles sharing a vertex,
    /// copies of one triangle, long strips along the axis). Such a split is retried on the
    /// other axes, by decreasing extent, before the node becomes a leaf. Range (0, 1].
    double no_progress_fraction = 0.9;
    /// Cells are never made narrower than this many times the mean extent, along the split
    /// axis, of the node's whole (unclipped) triangles: the resolution is capped at
    /// (hi - lo) / (min_cell_width * mean extent). Slicing finer than the triangles only
    /// copies references. Range [0, 1e6]; 0 disables the cap.
    double min_cell_width = 1.0;
    /// Keep a split only if it lowers the expected cost of the surface-area model that
    /// sg-stats reports (stats.hpp, unit constants), with the cells taken as leaves: without
    /// it, every split that makes progress by counts is kept, also where it only copies
    /// references. A split that fails is retried on the other axes. (Whatever the settings, a
    /// cell that receives every one of its parent's triangles at two levels in a row becomes a
    /// leaf.)
    bool stop_by_cost = true;
    /// Cut each node's slab down to the tight extent of its clipped triangles along the split
    /// axis (the poster's bounding planes), so that a ray missing [lo, hi] skips the node.
    /// false makes lo and hi the node box's own faces: a plain nested grid, for sg-bench's
    /// sweep to show what the planes are worth.
    bool bounding_planes = true;
    /// Put one-cell nodes (bounding planes on a second or third axis) around a cell's
    /// contents where the triangles leave at least a quarter of the cell's surface area empty,
    /// so that a ray missing them skips the cell without walking or testing it. Each counts as
    /// a node and a level. false builds only the nodes the split rule makes (the poster's
    /// construction).
    bool bounding_nodes = true;
    /// Reference a triangle in a cell only if the triangle itself, clipped to the node's box
    /// in double precision, touches the cell. false uses the triangle's bounding box clipped
    /// to the node's box instead (cheaper to build, more references): for sg-bench's sweep.
    bool clip_triangles = true;
    /// Worker threads for the build; 0 means all hardware threads. Range [0, 1024]. The
    /// output is bit-identical for every value.
    std::uint32_t threads = 0;

    friend constexpr bool operator==(const BuildConfig&, const BuildConfig&) = default;
};

/// One field of BuildConfig as build_config_fields describes it: how to reach it, its valid
/// range and a help text. The default is the member's own initialiser (read it from
/// BuildConfig{} through `member`), so it is written down once.
struct BuildConfigField {
    using CountMember = std::uint32_t BuildConfig::*;  ///< a whole number
    using RealMember = double BuildConfig::*;          ///< a finite real number
    using SwitchMember = bool BuildConfig::*;          ///< on or off
    using Member = std::variant<CountMember, RealMember, SwitchMember>;

    /// The member's name: the JSON key, the .sg CONF slot and, with '_' as '-', the flag
    /// (`--leaf-size`; switches also get `--no-<name>`).
    std::string_view name;
    Member member;
    /// Valid range of a count or a real: [low, high], or (low, high] when low_open. Unused for
    /// switches.
    double low = 0.0;
    double high = 0.0;
    bool low_open = false;
    /// The field this one may not exceed (resolution_min may not exceed resolution_max), or
    /// empty. Checked after every field's own range.
    std::string_view at_most;
    /// One paragraph for --help: what the field does (range and default are added by the
    /// tools from the entries above).
    std::string_view help;

    [[nodiscard]] constexpr bool is_switch() const noexcept
    {
        return std::holds_alternative<SwitchMember>(member);
    }
    [[nodiscard]] constexpr bool is_count() const noexcept
    {
        return std::holds_alternative<CountMember>(member);
    }
};

/// Every BuildConfig field, in declaration order (the order of the JSON keys). Adding a field
/// to BuildConfig means adding it here; formats/src/sg_file_layout.hpp then refuses to
/// compile until the field has a place in the .sg file's CONF record.
inline constexpr std::array<BuildConfigField, 12> build_config_fields{{
    {"resolution_min", &BuildConfig::resolution_min, 1, 1u << 20, false, "resolution_max",
     "Fewest cells of an inner node, used by small nodes near the leaves (2 makes them binary "
     "splits)."},
    {"resolution_max", &BuildConfig::resolution_max, 2, 1u << 20, false, {},
     "Most cells of an inner node, reached by nodes with several sigma triangles (near the "
     "root)."},
    {"resolution_sigma", &BuildConfig::resolution_sigma, 0.0, 1e9, true, {},
     "Width of the Gaussian resolution function, in triangles: a node with sigma triangles "
     "gets 39% of the way from min to max cells, 2 sigma 86%, 3 sigma 99%."},
    {"leaf_size", &BuildConfig::leaf_size, 1, 1u << 20, false, {},
     "A cell with at most this many triangles becomes a leaf."},
    {"max_depth", &BuildConfig::max_depth, 0, max_supported_depth, false, {},
     "Deepest inner node (the root is depth 0); cells of a node at this depth become "
     "leaves."},
    {"no_progress_fraction", &BuildConfig::no_progress_fraction, 0.0, 1.0, true, {},
     "A split makes no progress when two or more cells, or every non-empty cell, would "
     "receive more than this fraction of the node's triangles; it is retried on the other "
     "axes before the node becomes a leaf."},
    {"min_cell_width", &BuildConfig::min_cell_width, 0.0, 1e6, false, {},
     "Cells are never narrower than this many times the mean extent of the node's triangles "
     "along the split axis (slicing finer than the triangles only copies references); 0 "
     "disables the cap."},
    {"stop_by_cost", &BuildConfig::stop_by_cost, 0, 0, false, {},
     "Keep a split only if it lowers the expected traversal cost of the surface-area model "
     "(sg-stats), with its cells taken as leaves; a split that fails is retried on the other "
     "axes."},
    {"bounding_planes", &BuildConfig::bounding_planes, 0, 0, false, {},
     "Cut each node's slab down to the tight extent of its triangles along the split axis "
     "(the Split Grid's bounding planes); off, the slab is the node box itself: a plain "
     "nested grid."},
    {"bounding_nodes", &BuildConfig::bounding_nodes, 0, 0, false, {},
     "Put one-cell nodes (bounding planes on another axis) around a cell's triangles where "
     "they leave at least a quarter of the cell's surface area empty; off, only the split "
     "rule's nodes are built (the poster's construction)."},
    {"clip_triangles", &BuildConfig::clip_triangles, 0, 0, false, {},
     "Reference a triangle only in the cells the triangle itself touches (exact clipping); "
     "off, its bounding box decides, which builds faster and makes more references."},
    {"threads", &BuildConfig::threads, 0, 1024, false, {},
     "Worker threads for the build, 0 = all hardware threads; the output is bit-identical "
     "for every value."},
}};

/// The entry of build_config_fields called `name`, or nullptr.
[[nodiscard]] constexpr const BuildConfigField* find_build_config_field(std::string_view name)
{
    for (const BuildConfigField& field : build_config_fields)
        if (field.name == name) return &field;
    return nullptr;
}

/// The two named constructions (--preset in the tools). "default" is BuildConfig{}: the
/// fastest Split Grid this library makes. "poster" is the construction of the poster
/// (Bauszat, Kastner, Eisemann, Magnor, Eurographics 2014): nested 1D grids with bounding
/// planes, a Gaussian resolution and no cost function, so only the nodes its split rule makes
/// (no one-cell bounding nodes) and no cost test. It keeps the rules a build needs to end on
/// real meshes (no_progress_fraction, min_cell_width, a cell that keeps all of its parent's
/// triangles twice in a row becomes a leaf) and the tight-box axis choice and clipping;
/// docs/SPLIT_GRID.md lists every departure from the poster with its measured effect.
inline constexpr std::array<std::string_view, 2> build_preset_names{"default", "poster"};

/// `config` with preset `name` applied: "poster" switches off what the poster does not have
/// (bounding_nodes, stop_by_cost) and leaves every other field as it is; "default" changes
/// nothing. Throws ConfigError for any other name.
[[nodiscard]] BuildConfig apply_build_preset(BuildConfig config, std::string_view name);

/// Sets `field` of `config` from a number given by a caller that does not hold the field's own
/// type (a binding, a parser): a count must be a whole number, and a count or real must lie in
/// the field's range, else ConfigError with validate()'s message ("BuildConfig.leaf_size = -1 is
/// out of range [1, 1048576]"), also for values the field's type could not hold; for a switch
/// any non-zero value is on. Fields that may not exceed another are left to validate().
void set_build_config_field(BuildConfig& config, const BuildConfigField& field, double value);

/// Throws ConfigError naming the first field outside its range, e.g.
/// "BuildConfig.leaf_size = 0 is out of range [1, 1048576]", then the first field above the
/// one it may not exceed: "BuildConfig.resolution_min = 9 is above BuildConfig.resolution_max
/// = 8". Both come from build_config_fields.
void validate(const BuildConfig& config);

}  // namespace sg

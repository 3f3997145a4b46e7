#include "points_report.hpp"

#include <cmath>
#include <iostream>

#include "splitgrid/version.hpp"

#include <spdlog/fmt/fmt.h>

namespace sg::apps {
namespace {

Json optional_number(std::optional<float> value) { return value ? Json(*value) : Json(nullptr); }

Json grid_json(const SamplingGrid& grid, double padding)
{
    Json j;
    j["dimensions"] = grid.counts;
    j["origin"] = grid.origin;
    j["spacing"] = grid.spacing;
    j["padding"] = padding;
    return j;
}

void print_json(const PointsRun& run, const AnswerCounts& counts, double points_per_second)
{
    const PointsOptions& o = *run.options;
    Json j;
    j["schema_version"] = json_schema_version;
    j["splitgrid_version"] = version_string;
    j["file"] = o.file.string();
    if (run.grid) {
        j["grid"] = grid_json(*run.grid, o.padding);
    } else {
        j["points_file"] = o.points.string();
        j["points_format"] = run.points_from_text ? "text" : "binary";
    }
    j["output"] = o.out.string();
    j["query"] = query_name(o.query);
    j["isa"] = run.isa;
    if (casts_rays(o.query)) j["nsamples"] = o.nsamples;
    if (measures_distance(o.query))
        j["max_distance"] = std::isinf(o.max_distance) ? Json(nullptr) : Json(o.max_distance);
    j["threads"] = run.threads;
    j["point_count"] = counts.points;
    if (casts_rays(o.query)) {
        j["inside"] = counts.inside;
        j["outside"] = counts.outside;
    }
    if (measures_distance(o.query)) {
        j["beyond_max_distance"] = counts.beyond;
        j["answer_min"] = optional_number(counts.least);
        j["answer_max"] = optional_number(counts.greatest);
    }
    j["nonfinite_points"] = counts.nonfinite;
    if (run.edges) j["edges"] = to_json(*run.edges);
    j["seconds"] = run.seconds;
    j["points_per_second"] = points_per_second;
    std::cout << j.dump(2) << '\n';
}

std::string plural(std::size_t n, const char* word)
{
    return fmt::format("{} {}{}", n, word, n == 1 ? "" : "s");
}

/// "0.0123 to 4.56" or "none".
std::string range_text(const AnswerCounts& counts)
{
    if (!counts.least) return "no finite answer";
    return fmt::format("{:.6g} to {:.6g}", *counts.least, *counts.greatest);
}

}  // namespace

AnswerCounts count_answers(PointQuery query, const PointAnswers& answers, std::size_t nonfinite)
{
    AnswerCounts counts;
    counts.nonfinite = nonfinite;
    const auto distance_seen = [&](float d) {
        if (std::isnan(d)) return;
        if (std::isinf(d)) {
            ++counts.beyond;
            return;
        }
        counts.least = counts.least ? std::min(*counts.least, d) : d;
        counts.greatest = counts.greatest ? std::max(*counts.greatest, d) : d;
    };
    if (query == PointQuery::closest) {
        counts.points = answers.closest.size();
        for (const ClosestPoint& c : answers.closest) distance_seen(c.distance);
        return counts;
    }
    counts.points = answers.values.size();
    for (const float v : answers.values) {
        if (query == PointQuery::occupancy) {
            counts.inside += v == 1.0f ? 1 : 0;
            counts.outside += v == 0.0f ? 1 : 0;
            continue;
        }
        distance_seen(v);
        if (query == PointQuery::signed_distance && std::isfinite(v))
            (v < 0.0f ? counts.inside : counts.outside) += 1;
    }
    return counts;
}

void report_points(const PointsRun& run, const AnswerCounts& counts)
{
    const PointsOptions& o = *run.options;
    const double points_per_second =
        run.seconds > 0.0 ? static_cast<double>(counts.points) / run.seconds : 0.0;
    if (o.json) {
        print_json(run, counts, points_per_second);
        return;
    }
    if (!o.log.shows_summary()) return;
    std::string what = fmt::format("{} of {}", query_name(o.query), plural(counts.points, "point"));
    if (run.grid)
        what += fmt::format(" on a {}x{}x{} grid", run.grid->counts[0], run.grid->counts[1],
                            run.grid->counts[2]);
    if (casts_rays(o.query)) what += fmt::format(" ({} per point)", plural(o.nsamples, "ray"));
    std::string answers;
    switch (o.query) {
    case PointQuery::occupancy:
        answers = fmt::format("{} inside, {} outside", counts.inside, counts.outside);
        break;
    case PointQuery::signed_distance:
        answers = fmt::format("{} inside, {} outside, signed distances {}", counts.inside,
                              counts.outside, range_text(counts));
        break;
    case PointQuery::distance:
    case PointQuery::closest:
        answers = fmt::format("distances {}", range_text(counts));
        break;
    }
    if (measures_distance(o.query) && !std::isinf(o.max_distance))
        answers += fmt::format(", {} beyond --max-distance {}", counts.beyond, o.max_distance);
    std::cout << fmt::format(
        "{} on {} in {:.3f} s: {:.0f} points/s; {}, {} non-finite, "
        "written to {}\n",
        what, plural(static_cast<std::size_t>(run.threads), "thread"), run.seconds,
        points_per_second, answers, counts.nonfinite, o.out.string());
}

}  // namespace sg::apps

// rapidcheck generators of scene specs (scene_case.h), one per property. Every knob is drawn
// from an rc::gen primitive, so shrinking simplifies the scene along it: fewer rods, lower
// complexity (the synth waviness knob), wider crossing angles, shorter rods, rods kept
// inside the picture, larger (rounder) rings, seed 0, the first transform.
#pragma once

#include <cstdint>
#include <string>

#include <rapidcheck.h>

#include "mbest/synth/config.h"
#include "scene_case.h"

namespace mbest::properties::gen {

// A data set seed drawn uniformly from [0, 2^31) whatever rapidcheck's size; shrinks to 0.
inline rc::Gen<std::uint64_t> seed() {
  return rc::gen::resize(100, rc::gen::inRange<std::uint64_t>(0, std::uint64_t{1} << 31));
}

// simplest + k * (other - simplest) / steps for k in [0, steps]: shrinks toward `simplest`.
inline rc::Gen<double> knob(double simplest, double other, int steps) {
  return rc::gen::map(rc::gen::inRange(0, steps + 1), [=](int k) {
    return simplest + (other - simplest) * k / steps;
  });
}

inline nlohmann::json range(double lo, double hi) { return nlohmann::json::array({lo, hi}); }
inline nlohmann::json range(int lo, int hi) { return nlohmann::json::array({lo, hi}); }

// Two rods (preset s2's tubes) made to cross once at 20-90 deg, complexity 0-0.5.
inline rc::Gen<SceneSpec> two_rods() {
  return rc::gen::apply(
      [](double angle, double complexity, double length, bool leave, std::uint64_t seed) {
        SceneSpec s;
        s.property = "two_rods";
        s.preset = "s2";
        s.overrides = {{"scene",
                        {{"rods", range(2, 2)},
                         {"planned_crossings", 1},
                         {"crossings", range(1, 1)},
                         {"crossing_angle_deg", range(angle, angle)},
                         {"complexity", range(complexity, complexity)},
                         {"length_px", range(length, length)},
                         {"self_loop", 0},
                         {"leave_image", leave ? 0.7 : 0.0}}}};
        s.seed = seed;
        return s;
      },
      knob(90, 20, 70), knob(0, 0.5, 50), knob(500, 1400, 45), rc::gen::arbitrary<bool>(), seed());
}

// One rod (preset s1's tube) kept inside the picture, no loop, complexity 0-0.65.
inline rc::Gen<SceneSpec> one_rod() {
  return rc::gen::apply(
      [](double complexity, double length, std::uint64_t seed) {
        SceneSpec s;
        s.property = "one_rod";
        s.preset = "s1";
        s.overrides = {{"scene",
                        {{"rods", range(1, 1)},
                         {"complexity", range(complexity, complexity)},
                         {"length_px", range(length, length)},
                         {"self_loop", 0},
                         {"leave_image", 0}}}};
        s.seed = seed;
        return s;
      },
      knob(0, 0.65, 65), knob(300, 1000, 35), seed());
}

// Preset s3's scenes with 1-3 rods, complexity 0-0.65, loops or not, under one transform.
inline rc::Gen<SceneSpec> equivariance() {
  return rc::gen::apply(
      [](std::string transform, int rods, double complexity, bool loops, std::uint64_t seed) {
        SceneSpec s;
        s.property = "equivariance";
        s.preset = "s3";
        s.overrides = {{"scene",
                        {{"rods", range(rods, rods)},
                         {"complexity", range(complexity, complexity)},
                         {"self_loop", loops ? 0.25 : 0.0}}}};
        s.seed = seed;
        s.transform = transform;
        return s;
      },
      rc::gen::element<std::string>("rot180", "flip_x", "flip_y", "transpose", "rot90", "rot270"),
      rc::gen::inRange(1, 4), knob(0, 0.65, 65), rc::gen::arbitrary<bool>(), seed());
}

// Any preset, its rod count and complexity anywhere in the preset's ranges, any seed.
inline rc::Gen<SceneSpec> any_scene() {
  return rc::gen::mapcat(rc::gen::element<std::string>("s1", "s2", "s3", "cables", "stress"),
                         [](const std::string& preset) {
    const synth::SynthConfig base = synth::preset_config(preset).value();
    const auto& sc = base.scene;
    return rc::gen::apply(
        [preset](int rods, double complexity, std::uint64_t seed) {
          SceneSpec s;
          s.property = "any_scene";
          s.preset = preset;
          s.overrides = {{"scene",
                          {{"rods", range(rods, rods)},
                           {"complexity", range(complexity, complexity)}}}};
          s.seed = seed;
          return s;
        },
        rc::gen::inRange(static_cast<int>(sc.rods.lo), static_cast<int>(sc.rods.hi) + 1),
        knob(sc.complexity.lo, sc.complexity.hi, 20), seed());
  });
}

// One rod (preset s1's tube, or a thinner `cables` one) with one self-loop, kept inside the
// picture, complexity 0-0.4, the loop's size 2-6 rod widths (shrinking toward 6: rounder).
inline rc::Gen<SceneSpec> loop() {
  return rc::gen::apply(
      [](bool thin, double complexity, double loop_size, std::uint64_t seed) {
        SceneSpec s;
        s.property = "loop";
        s.preset = thin ? "cables" : "s1";
        s.overrides = {{"scene",
                        {{"rods", range(1, 1)},
                         {"complexity", range(complexity, complexity)},
                         {"length_px", range(700, 900)},
                         {"self_loop", 1},
                         {"loop_size", range(loop_size, loop_size)},
                         {"rings", 0},
                         {"parallel_strands", 0},
                         {"planned_crossings", 0},
                         {"triple_points", 0},
                         {"leave_image", 0}}}};
        s.seed = seed;
        return s;
      },
      rc::gen::arbitrary<bool>(), knob(0, 0.4, 40), knob(6, 2, 40), seed());
}

// One ring (preset s1's tube) of diameter 80-200 px, complexity 0-0.65.
inline rc::Gen<SceneSpec> ring() {
  return rc::gen::apply(
      [](double diameter, double complexity, std::uint64_t seed) {
        SceneSpec s;
        s.property = "ring";
        s.preset = "s1";
        s.overrides = {{"scene",
                        {{"rods", range(1, 1)},
                         {"rings", 1},
                         {"ring_diameter_px", range(diameter, diameter)},
                         {"complexity", range(complexity, complexity)},
                         {"self_loop", 0},
                         {"leave_image", 0}}}};
        s.seed = seed;
        return s;
      },
      knob(200, 80, 60), knob(0, 0.65, 65), seed());
}

// Three rods (preset s3's tubes) through one point, complexity 0-0.5.
inline rc::Gen<SceneSpec> triple() {
  return rc::gen::apply(
      [](double complexity, double length, bool leave, std::uint64_t seed) {
        SceneSpec s;
        s.property = "triple";
        s.preset = "s3";
        s.overrides = {{"scene",
                        {{"rods", range(3, 3)},
                         {"triple_points", 1},
                         {"complexity", range(complexity, complexity)},
                         {"length_px", range(length, length)},
                         {"self_loop", 0},
                         {"leave_image", leave ? 0.7 : 0.0}}}};
        s.seed = seed;
        return s;
      },
      knob(0, 0.5, 50), knob(500, 1400, 45), rc::gen::arbitrary<bool>(), seed());
}

}  // namespace mbest::properties::gen

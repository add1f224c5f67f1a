// tavis._tavis: the pybind11 layer over gym::GymVecEnv (docs/python.md). Images and
// observation.state are returned as numpy views of the simulator's buffers (no copy, read-only,
// their base is the env, so the env outlives them; the package copies them unless asked not to);
// the GIL is released while the env resets, steps, renders and while a built-in policy acts, and
// every call holds the env (gym::GymVecEnv::Exclusive), so a second thread gets RuntimeError. Bad
// input raises ValueError, an unknown name KeyError, before anything moves; memory the env cannot
// have raises MemoryError.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "batch/builtin_policies.h"
#include "batch/cell/cell_report.h"
#include "batch/cell/cell_settings.h"
#include "batch/gym/gym_vec_env.h"
#include "batch/scene_render.h"
#include "configs/yaml_reader.h"
#include "kinematics/action.h"
#include "scenarios/registry.h"

namespace py = pybind11;

namespace tavis::batch::python {
namespace {

constexpr int kActionSize = kinematics::action::kSize;

// A read-only numpy view of `data` whose base is `owner`.
py::array View(const py::dtype& dtype, std::vector<py::ssize_t> shape, std::vector<py::ssize_t> strides,
               const void* data, const py::object& owner) {
  py::array view(dtype, std::move(shape), std::move(strides), data, owner);
  view.attr("setflags")(py::arg("write") = false);
  return view;
}

// The images of each camera as (num_envs, H, W, 3) uint8, keyed by camera name. The batch is
// env-major (render::ImageBatch), so a camera's images are one view with the env stride.
py::dict Pixels(const py::object& self, const render::ImageBatch* images) {
  const gym::GymVecEnv& env = self.cast<const gym::GymVecEnv&>();
  py::dict pixels;
  if (images == nullptr) return pixels;
  const py::dtype u8 = py::dtype::of<uint8_t>();
  for (int camera = 0; camera < images->n_cameras(); ++camera) {
    const py::ssize_t height = images->height(camera);
    const py::ssize_t width = images->width(camera);
    const py::ssize_t env_stride =
        images->num_envs() > 1 ? images->rgb(1, camera) - images->rgb(0, camera) : height * width * 3;
    pixels[py::str(env.camera_names()[static_cast<std::size_t>(camera)])] =
        View(u8, {images->num_envs(), height, width, 3}, {env_stride, width * 3, 3, 1}, images->rgb(0, camera), self);
  }
  return pixels;
}

py::array AgentPos(const py::object& self) {
  const gym::GymVecEnv& env = self.cast<const gym::GymVecEnv&>();
  const py::ssize_t row = env.state_size();
  return View(py::dtype::of<float>(), {env.num_envs(), row},
              {row * static_cast<py::ssize_t>(sizeof(float)), sizeof(float)}, env.agent_pos(), self);
}

// The actions as a contiguous (num_envs x 19) float64 buffer; ValueError for another shape or a
// dtype other than float32 / float64.
std::vector<double> Actions(const gym::GymVecEnv& env, const py::handle& actions) {
  if (!py::isinstance<py::array>(actions)) {
    throw py::value_error("actions must be a numpy array of shape (" + std::to_string(env.num_envs()) + ", " +
                          std::to_string(kActionSize) + "), got " +
                          py::type::of(actions).attr("__name__").cast<std::string>());
  }
  const py::array array = py::reinterpret_borrow<py::array>(actions);
  const py::dtype dtype = array.dtype();
  if (dtype.kind() != 'f' || (dtype.itemsize() != 4 && dtype.itemsize() != 8)) {
    throw py::value_error("actions must have dtype float32 or float64, got " + dtype.attr("name").cast<std::string>());
  }
  if (array.ndim() != 2 || array.shape(0) != env.num_envs() || array.shape(1) != kActionSize) {
    std::string shape;
    for (py::ssize_t axis = 0; axis < array.ndim(); ++axis)
      shape += (axis ? ", " : "") + std::to_string(array.shape(axis));
    throw py::value_error("actions must have shape (" + std::to_string(env.num_envs()) + ", " +
                          std::to_string(kActionSize) + "), got (" + shape + ")");
  }
  const auto values = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(array);
  return std::vector<double>(values.data(), values.data() + values.size());
}

template <typename T>
py::array_t<T> Copy(const std::vector<T>& values) {
  return py::array_t<T>(static_cast<py::ssize_t>(values.size()), values.data());
}

py::array_t<bool> Flags(const std::vector<uint8_t>& values) {
  py::array_t<bool> flags(static_cast<py::ssize_t>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i) flags.mutable_data()[i] = values[i] != 0;
  return flags;
}

using Exclusive = gym::GymVecEnv::Exclusive;

// The env's keyword arguments, each declared once: its name (the Python keyword) and how its value
// is read into the config. The Python package checks their types first, naming the argument.
struct EnvArgument {
  const char* name;
  void (*read)(const py::handle& value, gym::GymVecEnvConfig& config);
};

scenarios::Split SplitNamed(const std::string& name) {
  try {
    return scenarios::ParseSplit(name);
  } catch (const std::invalid_argument& error) {
    throw gym::UnknownName(error.what());  // a name, as an unknown task or robot is
  }
}

using Config = gym::GymVecEnvConfig;
const std::vector<EnvArgument>& EnvArguments() {
  static const std::vector<EnvArgument> arguments = {
      // The scene (scene::SceneSpec), as every front end names it.
      {"task", [](const py::handle& v, Config& c) { c.scene.task = v.cast<std::string>(); }},
      {"robot", [](const py::handle& v, Config& c) { c.scene.robot = v.cast<std::string>(); }},
      {"split", [](const py::handle& v, Config& c) { c.scene.split = SplitNamed(v.cast<std::string>()); }},
      {"seed", [](const py::handle& v, Config& c) { c.scene.seed = v.cast<uint64_t>(); }},
      {"perturbations",
       [](const py::handle& v, Config& c) { c.scene.perturbations = v.cast<std::vector<std::string>>(); }},
      {"config_dir", [](const py::handle& v, Config& c) { c.scene.config_dir = v.cast<std::string>(); }},
      // The env's own.
      {"num_envs", [](const py::handle& v, Config& c) { c.num_envs = v.cast<int>(); }},
      {"camera", [](const py::handle& v, Config& c) { c.camera = v.cast<std::string>(); }},
      {"cameras", [](const py::handle& v, Config& c) { c.cameras = v.cast<std::vector<std::string>>(); }},
      {"image_size",
       [](const py::handle& v, Config& c) {
         std::tie(c.image_height, c.image_width) = v.cast<std::pair<int, int>>();  // (height, width)
       }},
      {"threads", [](const py::handle& v, Config& c) { c.threads = v.cast<int>(); }},
      {"control_ticks_per_step", [](const py::handle& v, Config& c) { c.control_ticks_per_step = v.cast<int>(); }},
      {"autoreset", [](const py::handle& v, Config& c) { c.autoreset = v.cast<bool>(); }},
  };
  return arguments;
}

// The config the keyword arguments give; an argument the env does not take is a TypeError, as
// Python names one.
gym::GymVecEnvConfig EnvConfigFrom(const py::kwargs& given) {
  gym::GymVecEnvConfig config;
  config.scene.config_dir = TAVIS_DEFAULT_CONFIG_DIR;
  for (const auto& [key, value] : given) {
    const std::string name = key.cast<std::string>();
    const auto argument = std::find_if(EnvArguments().begin(), EnvArguments().end(),
                                       [&](const EnvArgument& known) { return name == known.name; });
    if (argument == EnvArguments().end())
      throw py::type_error("VecEnvCore() got an unexpected keyword argument '" + name + "'");
    argument->read(value, config);
  }
  return config;
}

gym::GymVecEnv* MakeEnv(gym::GymVecEnvConfig config) {
  py::gil_scoped_release release;
  return new gym::GymVecEnv(config);
}

// Python exceptions for the library's: a bad name is a KeyError, a bad config a ValueError.
void RegisterExceptionTranslator() {
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      if (thrown) std::rethrow_exception(thrown);
    } catch (const gym::UnknownName& error) {
      PyErr_SetString(PyExc_KeyError, error.what());
    } catch (const configs::ConfigError& error) {
      PyErr_SetString(PyExc_ValueError, error.what());
    } catch (const gym::OutOfMemory& error) {
      PyErr_SetString(PyExc_MemoryError, error.what());
    } catch (const gym::EnvBusy& error) {
      PyErr_SetString(PyExc_RuntimeError, error.what());
    }
  });
}

// The module's constants and free functions.
void BindModuleFunctions(py::module_& m) {
  m.attr("ACTION_SIZE") = kActionSize;
  m.attr("MAX_ENVS") = gym::kMaxGymEnvs;
  m.attr("MAX_EPISODE") = gym::kMaxEpisode;
  // The most episodes one cell holds, as `tavis eval --episodes` allows (write_results' count).
  m.attr("MAX_CELL_EPISODES") = static_cast<int64_t>(cell::FindCellSetting("episodes")->range->high);
  m.attr("DEFAULT_CONFIG_DIR") = TAVIS_DEFAULT_CONFIG_DIR;
  m.def(
      "env_argument_names",
      [] {
        std::vector<std::string> names;
        for (const EnvArgument& argument : EnvArguments()) names.push_back(argument.name);
        return names;
      },
      "The keyword arguments VecEnvCore takes, in its order");
  m.def("camera_names", &SceneCameraNames, "The cameras: head, fixed, left_wrist, right_wrist");
  m.def("known_tasks", &scenarios::KnownTasks, "The tasks, comma-separated");
  m.def("builtin_policy_names", &BuiltinPolicyNames);
}

// The built-in policy objects VecEnvCore.make_policy hands out.
void BindBuiltinPolicy(py::module_& m) {
  py::class_<Policy, std::shared_ptr<Policy>>(m, "BuiltinPolicy",
                                              "A built-in policy bound to one env (VecEnvCore.make_policy)")
      .def_property_readonly("name", &Policy::name)
      .def_property_readonly("control_ticks_per_action", &Policy::control_ticks_per_action);
}

// VecEnvCore's reset and step.
void BindStepping(py::class_<gym::GymVecEnv>& core) {
  core.def(
          "reset",
          [](gym::GymVecEnv& env, const std::vector<uint8_t>& mask, const std::vector<int64_t>& episodes) {
            const Exclusive use(env, "reset");
            py::gil_scoped_release release;
            env.Reset(mask, episodes);
          },
          py::arg("mask"), py::arg("episodes"))
      .def(
          "step",
          [](gym::GymVecEnv& env, const py::handle& actions) {
            const std::vector<double> values = Actions(env, actions);
            const Exclusive use(env, "step");
            py::gil_scoped_release release;
            env.Step(values.data());
          },
          py::arg("actions"));
}

// VecEnvCore's observation: images, observation.state, prompts, episode indices.
void BindObservation(py::class_<gym::GymVecEnv>& core) {
  core.def(
          "pixels",
          [](const py::object& self) {
            const gym::GymVecEnv& env = self.cast<const gym::GymVecEnv&>();
            const Exclusive use(env, "pixels");
            return Pixels(self, env.images());
          },
          "Views of the current images, {camera: (N, H, W, 3) uint8}, valid until the next step")
      .def(
          "final_pixels",
          [](const py::object& self) {
            const gym::GymVecEnv& env = self.cast<const gym::GymVecEnv&>();
            const Exclusive use(env, "final_pixels");
            return Pixels(self, env.final_images());
          },
          "Views of the images of the envs whose episode ended in this step, at their final state "
          "({} before any ended); other rows are stale")
      .def(
          "agent_pos",
          [](const py::object& self) {
            const Exclusive use(self.cast<const gym::GymVecEnv&>(), "agent_pos");
            return AgentPos(self);
          },
          "A view of observation.state, (N, D) float32, valid until the next step")
      .def("prompts",
           [](const gym::GymVecEnv& env) {
             const Exclusive use(env, "prompts");
             std::vector<std::string> prompts;
             for (int i = 0; i < env.num_envs(); ++i) prompts.emplace_back(env.prompt(i));
             return prompts;
           })
      .def("episodes", [](const gym::GymVecEnv& env) {
        const Exclusive use(env, "episodes");
        std::vector<int64_t> episodes;
        for (int i = 0; i < env.num_envs(); ++i) episodes.push_back(env.episode(i));
        return Copy(episodes);
      });
}

// VecEnvCore's per-step outcome: rewards, terminations, and the ended episodes' final state.
void BindEpisodeEnds(py::class_<gym::GymVecEnv>& core) {
  core.def("rewards",
           [](const gym::GymVecEnv& env) {
             const Exclusive use(env, "rewards");
             return Copy(env.rewards());
           })
      .def("terminated",
           [](const gym::GymVecEnv& env) {
             const Exclusive use(env, "terminated");
             return Flags(env.terminated());
           })
      .def("truncated",
           [](const gym::GymVecEnv& env) {
             const Exclusive use(env, "truncated");
             return Flags(env.truncated());
           })
      .def("ended",
           [](const gym::GymVecEnv& env) {
             const Exclusive use(env, "ended");
             return Flags(env.ended());
           })
      .def("ended_episodes",
           [](const gym::GymVecEnv& env) {
             const Exclusive use(env, "ended_episodes");
             return Copy(env.ended_episode());
           })
      .def("ended_how",
           [](const gym::GymVecEnv& env) {
             const Exclusive use(env, "ended_how");
             std::vector<std::string> ends;
             for (engine::EpisodeEnd end : env.ended_how()) ends.emplace_back(engine::ToString(end));
             return ends;
           })
      .def("final_agent_pos", [](const gym::GymVecEnv& env) {
        const Exclusive use(env, "final_agent_pos");
        py::array_t<float> rows({env.num_envs(), env.state_size()});
        std::copy(env.final_state().begin(), env.final_state().end(), rows.mutable_data());
        return rows;
      });
}

// VecEnvCore's built-in policies, run in C++ for the whole batch.
void BindPolicies(py::class_<gym::GymVecEnv>& core) {
  core.def(
          "make_policy",
          [](gym::GymVecEnv& env, const std::string& name, const std::string& actions_file) {
            const Exclusive use(env, "make_policy");
            py::gil_scoped_release release;
            return env.MakePolicy(name, actions_file);
          },
          py::arg("name"), py::arg("actions_file") = "", py::keep_alive<0, 1>())
      .def(
          "act",
          [](gym::GymVecEnv& env, Policy& policy) {
            py::array_t<double> actions({env.num_envs(), kActionSize});
            double* data = actions.mutable_data();
            {
              const Exclusive use(env, "act");
              py::gil_scoped_release release;
              env.Act(policy, data);
            }
            return actions;
          },
          py::arg("policy"))
      .def(
          "neutral_actions",
          [](gym::GymVecEnv& env) {
            py::array_t<double> actions({env.num_envs(), kActionSize});
            double* data = actions.mutable_data();
            {
              const Exclusive use(env, "neutral_actions");
              py::gil_scoped_release release;
              env.NeutralActions(data);
            }
            return actions;
          },
          "The hold policy's actions for every env, (N, 19) float64: arms at their reset pose, head "
          "still, grippers open");
}

// VecEnvCore's records, as tavis eval writes them.
void BindResults(py::class_<gym::GymVecEnv>& core) {
  core.def("episode_json_lines",
           [](const gym::GymVecEnv& env) {
             const Exclusive use(env, "episode_json_lines");
             std::vector<std::string> lines;
             for (const auto& [episode, record] : env.records())
               lines.push_back(cell::EpisodeJsonLine(record, env.config().scene.seed));
             return lines;
           })
      .def(
          "write_results",
          [](const gym::GymVecEnv& env, const std::string& out_dir, const std::string& policy, int64_t first,
             int64_t count, bool overwrite) {
            const Exclusive use(env, "write_results");
            py::gil_scoped_release release;
            env.WriteResults(out_dir, policy, first, count, overwrite);
          },
          py::arg("out_dir"), py::arg("policy"), py::arg("first"), py::arg("count"), py::arg("overwrite"));
}

}  // namespace
}  // namespace tavis::batch::python

PYBIND11_MODULE(_tavis, m) {
  using namespace tavis;                 // NOLINT: the module's one scope
  using namespace tavis::batch;          // NOLINT
  using namespace tavis::batch::python;  // NOLINT: the helpers above
  m.doc() = "TAVIS-C++ batched env (the pybind11 core of the tavis package; see docs/python.md)";
  RegisterExceptionTranslator();
  BindModuleFunctions(m);
  BindBuiltinPolicy(m);
  py::class_<gym::GymVecEnv> core(m, "VecEnvCore");
  core.def(py::init([](const py::kwargs& arguments) { return MakeEnv(EnvConfigFrom(arguments)); }),
           "VecEnvCore(**arguments): the env's keyword arguments (env_argument_names()), each read into "
           "gym::GymVecEnvConfig; one not given keeps its default")
      .def_property_readonly("num_envs", &gym::GymVecEnv::num_envs)
      .def_property_readonly("state_size", &gym::GymVecEnv::state_size)
      .def_property_readonly("control_ticks_per_step", &gym::GymVecEnv::control_ticks_per_step)
      .def_property_readonly("max_episode_steps", &gym::GymVecEnv::max_episode_steps)
      .def_property_readonly("camera_names", &gym::GymVecEnv::camera_names)
      .def_property_readonly("busy", &gym::GymVecEnv::busy, "Whether a call holds the env now (another thread's)");
  BindStepping(core);
  BindObservation(core);
  BindEpisodeEnds(core);
  BindPolicies(core);
  BindResults(core);
}

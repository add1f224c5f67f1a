#include "batch/rollout/episode_videos.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "batch/dataset/video/video_writer.h"
#include "batch/output/atomic_file.h"
#include "batch/output/output_folder.h"
#include "batch/output/setting_error.h"
#include "batch/rollout/observed_cameras.h"
#include "batch/rollout/video_frame.h"
#include "scenarios/stage_progress.h"

namespace tavis::batch::rollout {
namespace {

namespace fs = std::filesystem;

std::string StepCaption(int64_t episode, int control_step, int ticks_per_frame, double control_hz) {
  char text[96];
  std::snprintf(text, sizeof(text), "episode %lld   step %d   %.2f s", static_cast<long long>(episode),
                control_step / ticks_per_frame, control_step / control_hz);
  return text;
}

std::string OutcomeCaption(const cell::EpisodeRecord& record) {
  std::string text = engine::ToString(record.end);
  if (record.end == engine::EpisodeEnd::kInvalidAction && !record.invalid_action.reason.empty()) {
    text += " (" + record.invalid_action.reason + ")";
  }
  if (record.galt) {
    char galt[64];
    if (record.galt->galt_s) {
      std::snprintf(galt, sizeof(galt), "   GALT %.2f s", *record.galt->galt_s);
    } else {
      std::snprintf(galt, sizeof(galt), "   GALT none (%s)", kinematics::ToString(record.galt->reason));
    }
    text += galt;
  }
  return text;
}

}  // namespace

struct EpisodeVideoRecorder::Film {
  int64_t episode = 0;
  std::optional<dataset::video::EpisodeEncoder> encoder;  // mp4
  int64_t frames = 0;
  std::vector<render::RgbImage> end_views;  // [camera] at the episode's end
  std::string prompt;
  std::optional<scenarios::StageProgress> stages;  // shown in the caption as the episode goes
  std::vector<std::string> stage_names;

  std::vector<cell::StageReached> StagesSoFar() const {
    std::vector<cell::StageReached> reached;
    for (std::size_t i = 0; i < stage_names.size(); ++i) reached.push_back({stage_names[i], stages->first_ticks()[i]});
    return reached;
  }
};

std::string StageCaption(const std::vector<cell::StageReached>& stages) {
  if (stages.empty()) return "";
  int furthest = -1;
  for (std::size_t i = 0; i < stages.size(); ++i) {
    if (stages[i].reached()) furthest = static_cast<int>(i);
  }
  return "   stage " + std::to_string(furthest + 1) + "/" + std::to_string(stages.size()) + " " +
         (furthest >= 0 ? stages[static_cast<std::size_t>(furthest)].name : std::string("none yet"));
}

VideoFormat ParseVideoFormat(const std::string& text) {
  if (text == "mp4") return VideoFormat::kMp4;
  if (text == "png") return VideoFormat::kPng;
  throw std::invalid_argument("unknown video format '" + text + "' (known: mp4, png)");
}

void ValidateEpisodeVideoSettings(const EpisodeVideoSettings& settings) {
  if (settings.episodes < 0)
    throw output::SettingError("videos", "must be at least 0, got " + std::to_string(settings.episodes));
  const std::string size = std::to_string(settings.tile_width) + "x" + std::to_string(settings.tile_height);
  if (settings.tile_width < 64 || settings.tile_height < 48 || settings.tile_width % 2 != 0 ||
      settings.tile_height % 2 != 0) {
    throw output::SettingError("video_size",
                               "must be even and at least 64x48 (the encoder's yuv420p halves it), got " + size);
  }
  CameraSettings cameras;
  cameras.cameras = settings.cameras;
  ValidateCameraSettings(cameras);
}

std::vector<std::string> VideoCameras(const EpisodeVideoSettings& settings,
                                      const std::vector<std::string>& policy_cameras, CameraProtocol protocol) {
  if (!settings.cameras.empty()) return settings.cameras;
  std::vector<std::string> cameras = ObservedCameras(policy_cameras, protocol);
  if (std::find(cameras.begin(), cameras.end(), "fixed") == cameras.end()) cameras.push_back("fixed");
  return cameras;
}

std::string EpisodeVideoName(int64_t episode, VideoFormat format) {
  return "episode_" + std::to_string(episode) + (format == VideoFormat::kMp4 ? ".mp4" : "");
}

bool HasFinishedVideo(const fs::path& videos, int64_t episode, VideoFormat format) {
  std::error_code error;
  const fs::file_status status = fs::symlink_status(videos / EpisodeVideoName(episode, format), error);
  return format == VideoFormat::kMp4 ? fs::is_regular_file(status) : fs::is_directory(status);
}

EpisodeVideoRecorder::EpisodeVideoRecorder(const VecEnv& vec_env, EpisodeVideoSettings settings,
                                           std::vector<std::string> cameras, int64_t cell_start,
                                           std::function<fs::path()> folder)
    : settings_(std::move(settings)),
      cameras_(std::move(cameras)),
      cell_start_(cell_start),
      folder_(std::move(folder)),
      ticks_per_frame_(vec_env.model().physics.controls_per_policy()),
      control_hz_(vec_env.model().physics.control_hz),
      running_(static_cast<std::size_t>(vec_env.num_envs())),
      render_slots_(static_cast<std::size_t>(vec_env.num_envs()), 0) {
  ValidateEpisodeVideoSettings(settings_);
  CameraSettings camera_settings;
  camera_settings.cameras = cameras_;
  camera_settings.width = settings_.tile_width;
  camera_settings.height = settings_.tile_height;
  render_ = std::make_unique<SceneRender>(vec_env.model(), vec_env.num_envs(), camera_settings);
  // The task's black cameras are black here too, as the policy receives them.
  for (const std::string& name : vec_env.scenario().black_cameras) {
    const int camera = render_->CameraIndex(name);
    if (camera < 0) continue;
    for (int slot = 0; slot < vec_env.num_envs(); ++slot) render_->SetCameraEnabled(slot, camera, false);
  }
  std::tie(video_.width, video_.height) =
      VideoFrameSize(static_cast<int>(cameras_.size()), settings_.tile_width, settings_.tile_height);
  video_.fps = static_cast<int>(vec_env.model().physics.policy_hz + 0.5);
  video_.gop = video_.fps;  // a keyframe a second: these are watched, not sampled frame by frame
  dataset::video::ValidateVideoSettings(video_, "episode videos");
}

EpisodeVideoRecorder::~EpisodeVideoRecorder() = default;

bool EpisodeVideoRecorder::Filmed(int64_t episode) const {
  return episode >= cell_start_ && episode - cell_start_ < settings_.episodes;
}

void EpisodeVideoRecorder::EpisodeStarted(const VecEnv& vec_env, int slot) {
  std::unique_ptr<Film>& film = running_[static_cast<std::size_t>(slot)];
  film.reset();
  const int64_t episode = vec_env.state().episode[slot];
  if (!Filmed(episode)) return;
  film = std::make_unique<Film>();
  film->episode = episode;
  film->prompt = vec_env.prompt(slot);
  film->stages.emplace(vec_env.scenario(), vec_env.model());
  film->stages->Start();
  for (const scenarios::StageDef& stage : vec_env.scenario().stages) film->stage_names.push_back(stage.name);
  if (settings_.format == VideoFormat::kMp4) {
    film->encoder.emplace(video_, EpisodeVideoName(episode, settings_.format));
  } else {
    // The frames fill FOLDER.partial, renamed to FOLDER once the last is written (RecordFinished).
    output::MakeOwnFolder(folder_());
    const fs::path frames = folder_() / (EpisodeVideoName(episode, settings_.format) + ".partial");
    fs::remove_all(frames);  // a film cut short, or a link: a rerun episode is filmed from its start
    fs::create_directory(frames);
  }
}

render::RgbImage EpisodeVideoRecorder::Frame(int slot, const std::vector<std::string>& caption) const {
  const render::ImageBatch& images = render_->images();
  std::vector<render::LabelledImage> views;
  for (int camera = 0; camera < render_->num_cameras(); ++camera) {
    views.push_back({cameras_[static_cast<std::size_t>(camera)], images.height(camera), images.width(camera),
                     images.rgb(slot, camera)});
  }
  return ComposeVideoFrame(views, caption);
}

void EpisodeVideoRecorder::Write(Film& film, const render::RgbImage& frame) {
  if (film.encoder) {
    film.encoder->WriteFrame(frame.pixels.data(), frame.pixels.size());
  } else {
    char name[32];
    std::snprintf(name, sizeof(name), "frame_%05lld.png", static_cast<long long>(film.frames));
    render::WritePng((folder_() / (EpisodeVideoName(film.episode, settings_.format) + ".partial") / name).string(),
                     frame);
  }
  ++film.frames;
}

void EpisodeVideoRecorder::TickStarting(const VecEnv& vec_env) {
  const engine::BatchState& state = vec_env.state();
  bool any = false;
  for (int slot = 0; slot < vec_env.num_envs(); ++slot) {
    // What the policy observes: the state at each of the episode's policy ticks, before it acts.
    const bool take = running_[static_cast<std::size_t>(slot)] && state.running(slot) &&
                      state.control_step[slot] % ticks_per_frame_ == 0;
    render_slots_[static_cast<std::size_t>(slot)] = take ? 1 : 0;
    any = any || take;
  }
  if (!any) return;
  render_->Render(state, render_slots_.data());
  // Each filmed slot has its own encoder (or files): compose and encode them in parallel.
  tbb::parallel_for(0, vec_env.num_envs(), [&](int slot) {
    if (!render_slots_[static_cast<std::size_t>(slot)]) return;
    Film& film = *running_[static_cast<std::size_t>(slot)];
    Write(film, Frame(slot, {StepCaption(film.episode, state.control_step[slot], ticks_per_frame_, control_hz_) +
                                 StageCaption(film.StagesSoFar()),
                             film.prompt}));
  });
}

void EpisodeVideoRecorder::ActionChosen(const VecEnv& vec_env, int slot, const kinematics::Action&) {
  // Every control tick's state, as the cell's recorder follows the stages, so the caption agrees
  // with the episode's record.
  const std::unique_ptr<Film>& film = running_[static_cast<std::size_t>(slot)];
  if (film) film->stages->Observe(vec_env.state(), slot);
}

void EpisodeVideoRecorder::EpisodeEnded(const VecEnv& vec_env, int slot) {
  std::unique_ptr<Film>& film = running_[static_cast<std::size_t>(slot)];
  if (!film) return;
  std::fill(render_slots_.begin(), render_slots_.end(), 0);
  render_slots_[static_cast<std::size_t>(slot)] = 1;
  render_->Render(vec_env.state(), render_slots_.data());
  const render::ImageBatch& images = render_->images();
  for (int camera = 0; camera < render_->num_cameras(); ++camera) {
    render::RgbImage view;
    view.width = images.width(camera);
    view.height = images.height(camera);
    const uint8_t* rgb = images.rgb(slot, camera);
    view.pixels.assign(rgb, rgb + static_cast<std::size_t>(view.width) * static_cast<std::size_t>(view.height) * 3);
    film->end_views.push_back(std::move(view));
  }
  ended_[film->episode] = std::move(film);
}

void EpisodeVideoRecorder::RecordFinished(const cell::EpisodeRecord& record) {
  const auto found = ended_.find(record.episode);
  if (found == ended_.end()) return;
  Film& film = *found->second;
  std::vector<render::LabelledImage> views;
  for (std::size_t camera = 0; camera < film.end_views.size(); ++camera) {
    const render::RgbImage& view = film.end_views[camera];
    views.push_back({cameras_[camera], view.height, view.width, view.pixels.data()});
  }
  const render::RgbImage frame =
      ComposeVideoFrame(views, {StepCaption(film.episode, record.length_control_ticks, ticks_per_frame_, control_hz_) +
                                    StageCaption(record.stages),
                                OutcomeCaption(record)});
  // The video takes its name only once whole (a resume films again an episode without it).
  const fs::path video = folder_() / EpisodeVideoName(film.episode, settings_.format);
  if (film.encoder) {
    for (int hold = 0; hold < kOutcomeFrames; ++hold) Write(film, frame);
    const dataset::video::EncodedEpisode encoded = film.encoder->Finish();
    output::MakeOwnFolder(video.parent_path());
    output::FreshPartialPath(video);  // the writer's VIDEO.partial: a link planted there goes, unfollowed
    dataset::video::Mp4VideoWriter writer(video.string(), video_);
    writer.AppendEpisode(encoded);
    writer.Close();  // renames VIDEO.partial to VIDEO
  } else {
    Write(film, frame);
    fs::remove_all(video);  // an older film of it, rerun
    output::RenamePartialIntoPlace(video);
  }
  ended_.erase(found);
  ++videos_written_;
}

}  // namespace tavis::batch::rollout

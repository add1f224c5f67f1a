"""A factory for LeRobot >= 0.4 checkpoints (ACT, Diffusion, SmolVLA, pi0):

    python3 -m tavis_server --policy tavis_server.lerobot_checkpoint:load \\
        --policy-arg path=outputs/train/act_tavis/checkpoints/last/pretrained_model --device cuda

It loads the policy and the pre/post-processor pipelines saved next to it (normalisation,
tokenizer, device moves) and hands them to the server, which calls
    postprocess(policy.predict_action_chunk(preprocess(batch)))
once per request over the envs that need a forward pass (docs/serving.md: with
n_obs_steps > 1 the server's action queue answers the steps between passes, as select_action does).

NOT RUN: LeRobot cannot be installed in this project's environment (Debian's Python 3.11, no
pyarrow); this follows LeRobot's documented API (PreTrainedConfig.from_pretrained,
get_policy_class(type).from_pretrained(path, config=...), make_pre_post_processors(config,
pretrained_path=..., preprocessor_overrides=...)) and was only checked for syntax here."""


def load(path, device="cuda", n_action_steps=None):
    """(policy, preprocess, postprocess) for the checkpoint folder or Hub id `path`.
    n_action_steps: rows of each chunk the client gets (default: the checkpoint's)."""
    from lerobot.configs.policies import PreTrainedConfig
    from lerobot.policies.factory import get_policy_class, make_pre_post_processors

    config = PreTrainedConfig.from_pretrained(path)
    config.device = device
    if n_action_steps is not None:
        config.n_action_steps = int(n_action_steps)
    policy = get_policy_class(config.type).from_pretrained(path, config=config)
    policy.to(device).eval()
    preprocess, postprocess = make_pre_post_processors(
        config, pretrained_path=path, preprocessor_overrides={"device_processor": {"device": device}})
    return policy, preprocess, postprocess

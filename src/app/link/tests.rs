#![allow(clippy::unwrap_used)]

use super::*;
use crate::app::hook::shown;
use crate::app::initial_state;

fn sample_state() -> AppState {
    initial_state(&[], Default::default())
}

/// Applies a link's steps to `state` as the page does, frame after frame.
fn follow(link: &Link, state: &mut AppState) {
    let mut steps = link.steps();
    for _ in 0..10_000 {
        match steps.next(state) {
            None if !state.is_busy() => return,
            None => {}
            Some(Ok(commands)) => commands.into_iter().for_each(|c| state.apply(c)),
            Some(Err(why)) => panic!("{why}"),
        }
        state.advance(0.0);
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    panic!("the link's steps never ended");
}

#[test]
fn a_link_reads_back_as_itself() {
    let link = Link {
        demo: Some("R2b COM".to_owned()),
        recording: Some("box1-paper-ur-front/online_003".to_owned()),
        frame: Some(120),
        learned: Some(150),
        theta: Some([0.012_345_678_901_234_5, -1e-17, 0.061_000_000_000_000_01]),
        optimizer: Some(Optimizer::GaussNewton),
        lr: Some(0.005),
        speed: Some(0.5),
        learn: Some(false),
        layers: vec![("trails".to_owned(), false), ("what_if".to_owned(), true)],
        present: true,
        projector: true,
        light: true,
        hide: vec!["browser".to_owned(), "tools".to_owned()],
        sandbox: Some(7),
        object: Some("ellipse".to_owned()),
        challenge: true,
        com: Some([0.011, -0.002_5]),
    };
    let query = link.to_query();
    assert!(query.starts_with("demo=R2b%20COM&rec=box1-paper-ur-front/online_003&frame=120&"));
    assert!(query.contains("layers=-trails,what_if"), "{query}");
    assert_eq!(Link::parse(&format!("?{query}")), Ok(link));
}

#[test]
fn a_bad_link_is_refused_naming_the_field() {
    let cases = [
        (
            "theta=1,2",
            "link: theta=\"1,2\": expected x,y,h in metres, finite, h > 0",
        ),
        (
            "opt=adam",
            "link: opt=\"adam\": expected gd or gauss-newton",
        ),
        ("frame=-3", "link: frame=\"-3\": expected a frame number"),
        ("colour=red", "link: unknown field \"colour\""),
    ];
    for (query, message) in cases {
        assert_eq!(Link::parse(query), Err(message.to_owned()), "{query}");
    }
    let hide = Link::parse("hide=plots").expect_err("no such control");
    assert!(hide.contains("browser, tools, timeline, menu"), "{hide}");
    let layers = Link::parse("layers=-nope").expect_err("no such layer");
    assert!(layers.contains("com_ellipse"), "{layers}");
}

#[test]
fn opening_a_link_shows_the_same_frame_theta_and_losses() {
    let mut shared = sample_state();
    let last = shared.session().recordings().count() - 1;
    let (id, _) = shared.session().recordings().nth(last / 2).expect("a push");
    shared.apply(Command::Session(SessionCommand::Select(id)));
    shared.apply(Command::Online(OnlineCommand::SetLearnWhilePlaying(true)));
    shared.apply(Command::Timeline(TimelineCommand::SeekTo(38)));
    shared.apply(Command::Timeline(TimelineCommand::SeekTo(37)));
    for _ in 0..10_000 {
        if !shared.is_busy() {
            break;
        }
        shared.advance(0.0);
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    let link = Link::of(&shared, &ViewPart::default());
    assert_eq!((link.frame, link.learned), (Some(37), Some(38)));

    let mut opened = sample_state();
    follow(&Link::parse(&link.to_query()).expect("parses"), &mut opened);
    let (mut want, mut got) = (shown(&shared), shown(&opened));
    want.status = None;
    got.status = None;
    assert_eq!(got, want);
    assert!(got.online_loss.is_some(), "frame 37 was learned");

    // A θ steered by hand comes back too.
    shared.apply(Command::Online(OnlineCommand::SetTheta(OnlineParams {
        com_offset: [0.011, -0.007],
        h: 0.05,
    })));
    let steered = Link::of(&shared, &ViewPart::default());
    let mut reopened = sample_state();
    follow(
        &Link::parse(&steered.to_query()).expect("parses"),
        &mut reopened,
    );
    assert_eq!(shown(&reopened).theta, shown(&shared).theta);
    assert_eq!(shown(&reopened).theta, Some([0.011, -0.007, 0.05]));
}

#[test]
fn the_view_a_link_asks_for_is_the_view_it_reads_back() {
    let asked = Link::parse("present=1&projector=1&light=1&hide=browser,menu").expect("parses");
    let mut view = crate::app::View::default();
    assert_eq!(view.link_part(), ViewPart::default());
    view.follow_link_part(&asked.view());
    assert!(!view.layout.is_shown(crate::app::layout::Pane::Browser));
    assert!(view.layout.is_shown(crate::app::layout::Pane::Tools));
    assert!(view.hide_menu && !view.hide_timeline);
    assert!(view.light);
    assert_eq!(view.link_part(), asked.view());
}

#[test]
fn a_sandbox_link_opens_the_same_mystery_and_leaves_the_pushes_out() {
    use crate::app::state::sources::sandbox::SandboxCommand;
    use pushlab_core::sandbox::{Mystery, MysteryObject};

    let mut teacher = sample_state();
    teacher.apply(Command::Sandbox(SandboxCommand::Start {
        seed: 42,
        object: Some(MysteryObject::T),
        noise: false,
        challenge: true,
        com: None,
    }));
    let rest = teacher.sandbox().unwrap().sandbox().pusher();
    teacher.apply(Command::Sandbox(SandboxCommand::Drag(vec![
        [rest.x, rest.y, 0.0],
        [rest.x + 0.3, rest.y, 8.0],
    ])));
    let view = ViewPart {
        hide: vec!["browser".to_owned(), "tools".to_owned()],
        ..ViewPart::default()
    };
    let query = Link::of(&teacher, &view).to_query();
    assert_eq!(query, "hide=browser,tools&sandbox=42&object=t&challenge=1");

    let link = Link::parse(&query).unwrap();
    let mut student = sample_state();
    follow(&link, &mut student);
    let opened = student.sandbox().expect("the link opens the sandbox");
    assert_eq!(
        opened.sandbox().mystery(),
        &Mystery::draw(42, MysteryObject::T).unwrap()
    );
    assert_eq!(
        opened.sandbox().mystery(),
        teacher.sandbox().unwrap().sandbox().mystery()
    );
    assert!(opened.challenge() && opened.sandbox().made().is_empty());
    assert_eq!(link.view().hide, ["browser", "tools"]);

    // A teacher's own hidden COM travels in the link; a bad one is refused by name.
    let link = Link::parse("sandbox=3&object=box&com=0.02,-0.01").unwrap();
    let mut class = sample_state();
    follow(&link, &mut class);
    let mystery = class.sandbox().unwrap().sandbox().mystery().clone();
    assert_eq!(mystery.hidden.com_offset, [0.02, -0.01]);
    assert_eq!(
        Link::of(&class, &ViewPart::default()).com,
        Some([0.02, -0.01])
    );
    let e = Link::parse("sandbox=3&object=sphere").unwrap_err();
    assert_eq!(e, "link: object=\"sphere\": expected box, t or ellipse");
    assert!(
        Link::parse("sandbox=-1")
            .unwrap_err()
            .contains("expected a seed")
    );
}

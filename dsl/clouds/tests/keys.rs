//! The reachable keys are every canonical key, each once, and key names tell them apart.

use std::collections::BTreeSet;

use nimbus_clouds::{CloudKey, PhaseKind, PhaseSpec, ShadowKey};

fn spec_of(kind: PhaseKind) -> PhaseSpec {
    match kind {
        PhaseKind::HenyeyGreenstein => PhaseSpec::HenyeyGreenstein { g: 0.7 },
        PhaseKind::DualLobe => PhaseSpec::DualLobe {
            g1: 0.7,
            g2: -0.2,
            weight: 0.5,
        },
        PhaseKind::ApproximateMie => PhaseSpec::ApproximateMie {
            droplet_diameter_um: 10.0,
        },
        PhaseKind::Isotropic => PhaseSpec::Isotropic,
        PhaseKind::IceCrystal => PhaseSpec::IceCrystal { g: 0.85, halo: 0.1 },
    }
}

#[test]
fn reachable_keys_are_canonical_distinct_and_named_apart() {
    let keys = CloudKey::reachable();
    // Twelve octave counts without the diffusion, one with it (it replaces the octaves); the
    // accurate air light never with an orthographic camera (which integrates the air anyway).
    assert_eq!(keys.len(), (4608 * 12 + 4608) * 5 * 2);
    let names: BTreeSet<String> = keys.iter().map(CloudKey::name).collect();
    assert_eq!(names.len(), keys.len(), "two keys share a name");
    for k in &keys {
        // Making the key from its own features gives it back: nothing non-canonical is reachable.
        assert_eq!(CloudKey::new(k.features, &spec_of(k.phase), k.groups), *k);
    }
    let shadows = ShadowKey::reachable();
    let names: BTreeSet<String> = shadows.iter().map(ShadowKey::name).collect();
    assert_eq!((shadows.len(), names.len()), (16, 16));
}

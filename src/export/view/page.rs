//! The page around the document: HTML, style, an error catcher, the data and the bundle.

use super::View;

/// The viewer bundle (three.js + `assets/viewer/src/viewer.js`), built by
/// `assets/viewer/build.sh`.
const BUNDLE: &str = include_str!("../../../assets/viewer/viewer.min.js");

/// Console errors, uncaught exceptions and rejected promises, collected before anything else
/// runs into `window.ccrkitErrors` and the `<pre id="ccrkit-errors">` element, so a DOM dump
/// shows them.
const CATCHER: &str = r#"window.ccrkitErrors=[];(function(){function note(m){window.ccrkitErrors.push(String(m));var e=document.getElementById('ccrkit-errors');if(e)e.textContent=JSON.stringify(window.ccrkitErrors);}var ce=console.error;console.error=function(){note(Array.prototype.join.call(arguments,' '));ce.apply(console,arguments);};window.addEventListener('error',function(ev){note(ev.message||ev);});window.addEventListener('unhandledrejection',function(ev){note('unhandled rejection: '+ev.reason);});})();"#;

const STYLE: &str = "html,body{margin:0;height:100%;overflow:hidden;font:13px/1.35 sans-serif;color:#222}\
#view{position:absolute;inset:0}\
#legend{position:absolute;top:8px;left:8px;background:rgba(255,255,255,.88);padding:6px 9px;border:1px solid #ccc;border-radius:4px;max-width:42%}\
#legend .title{font-weight:bold;margin-bottom:3px}#legend .small{color:#666;font-size:11px}\
.swatch{display:inline-block;width:12px;height:12px;margin-right:6px;vertical-align:-2px;border-radius:2px}\
#controls{position:absolute;bottom:10px;left:50%;transform:translateX(-50%);background:rgba(255,255,255,.9);padding:5px 10px;border:1px solid #ccc;border-radius:4px;display:flex;gap:8px;align-items:center}\
#controls[hidden]{display:none}#controls input[type=range]{width:40vw}\
.colorbar{display:inline-block;width:120px;height:10px;background:linear-gradient(90deg,hsl(238,85%,45%),hsl(119,85%,45%),hsl(0,85%,45%))}";

fn escape_html(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The whole page.
pub(super) fn html(title: &str, view: &View) -> String {
    // `<` never appears raw inside the script element (no `</script>` in the data).
    let data = serde_json::to_string(view)
        .unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
        .replace('<', "\\u003c");
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
<meta name=\"viewport\" content=\"width=device-width,initial-scale=1\">\
<title>{t} — ccrkit view</title><style>{STYLE}</style><script>{CATCHER}</script></head>\n\
<body><div id=\"view\"></div><div id=\"legend\"></div><div id=\"controls\" hidden></div>\
<pre id=\"ccrkit-scene\" hidden></pre><pre id=\"ccrkit-errors\" hidden>[]</pre>\n\
<script>window.CCRKIT_DATA={data};</script>\n<script>{BUNDLE}</script>\n</body></html>\n",
        t = escape_html(title)
    )
}

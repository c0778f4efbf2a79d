// lpss-view in a real browser: placeholder until the page lands (see the next commit).
